//! Helpers shared by integration tests (`mod support;` in each test that uses them).

#[allow(dead_code, reason = "only the relation tests use the assemblies")]
pub(crate) mod assemblies;
#[allow(dead_code, reason = "only the snapping tests judge snaps")]
pub(crate) mod judge;
#[allow(dead_code, reason = "only the snapping tests draw overlays")]
pub(crate) mod overlay;
#[allow(
    dead_code,
    reason = "not every test binary uses every part of the renderer"
)]
pub(crate) mod synth;
