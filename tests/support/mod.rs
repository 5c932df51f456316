//! Helpers shared by integration tests (`mod support;` in each test that uses them).

pub(crate) mod synth;
