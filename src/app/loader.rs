//! Opening a drawing or a session off the UI thread: reading and importing the file,
//! sorting its strokes (ends and outlines) and preparing them for snapping run on a
//! thread of their own, which reports the step it is at, so the window keeps drawing
//! (and says what it is doing) however large the drawing is. The work in the window
//! stays as it is until the file is ready, and is then replaced in one go.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Receiver};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use anyhow::{anyhow, Context as _};

use super::worker::Wake;
use crate::core::sketch::{classify_sketch, ClassifyOptions, Sketch, StrokeClass, StrokeId};
use crate::core::snap::SnapContext;
use crate::io::session::{load_session, parse_session, Session};
use crate::io::sketch_file::load_sketch;

/// Which step an opening is at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Phase {
    /// Reading and importing the file.
    Reading,
    /// Telling ends from outlines among this many strokes.
    Sorting(usize),
    /// Preparing this many strokes for snapping.
    Preparing(usize),
}

impl Phase {
    /// The step in words ("sorting 2,900 strokes").
    pub(crate) fn text(self) -> String {
        match self {
            Self::Reading => "reading the file".to_owned(),
            Self::Sorting(n) => format!("sorting {} strokes into ends and outlines", thousands(n)),
            Self::Preparing(n) => format!("preparing {} strokes for snapping", thousands(n)),
        }
    }
}

/// `n` with a comma between thousands (2,900).
fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// What a file holds.
#[derive(Debug)]
pub(crate) enum Content {
    /// A drawing (native sketch or SVG), with its reference image and the importer's
    /// warnings.
    Drawing {
        sketch: Sketch,
        image: Option<PathBuf>,
        warnings: Vec<String>,
    },
    /// A saved session.
    Session(Box<Session>),
}

impl Content {
    fn sketch(&self) -> &Sketch {
        match self {
            Self::Drawing { sketch, .. } => sketch,
            Self::Session(session) => &session.sketch,
        }
    }
}

/// A file read and prepared: its content, its strokes' classes and their snapping
/// context.
#[derive(Debug)]
pub(crate) struct Loaded {
    pub content: Content,
    pub classes: Vec<(StrokeId, StrokeClass)>,
    pub context: SnapContext,
    /// How many duplicate strokes preparing merged into earlier ones (snapping sees
    /// each line once; the drawing keeps them).
    pub merged: usize,
}

/// A file being opened.
#[derive(Debug)]
pub(crate) struct Loading {
    /// The file.
    pub path: PathBuf,
    phase: Arc<Mutex<Phase>>,
    result: Receiver<anyhow::Result<Loaded>>,
    started: Instant,
}

impl Loading {
    /// Starts opening `path` (a session when `session`, else a drawing) on a thread;
    /// `wake` is called at each step and when it is done.
    pub(crate) fn start(path: &Path, session: bool, wake: Wake) -> Self {
        let phase = Arc::new(Mutex::new(Phase::Reading));
        let (sender, result) = channel();
        let (shared, file) = (Arc::clone(&phase), path.to_owned());
        let spawned = std::thread::Builder::new()
            .name("geosnap-open".into())
            .spawn(move || {
                let step = |p: Phase| {
                    *shared.lock().unwrap_or_else(PoisonError::into_inner) = p;
                    wake();
                };
                let loaded = load(&file, session, &step);
                // The window may have gone meanwhile; nobody to tell then.
                let _ = sender.send(loaded);
                wake();
            });
        if let Err(error) = spawned {
            log::error!("cannot start a thread to open a file: {error}");
        }
        Self {
            path: path.to_owned(),
            phase,
            result,
            started: Instant::now(),
        }
    }

    /// The step it is at.
    pub(crate) fn phase(&self) -> Phase {
        *self.phase.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// How long it has run.
    pub(crate) fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }

    /// The file read and prepared, or why it could not be, once done.
    pub(crate) fn try_result(&self) -> Option<anyhow::Result<Loaded>> {
        match self.result.try_recv() {
            Ok(result) => Some(result),
            Err(std::sync::mpsc::TryRecvError::Empty) => None,
            Err(std::sync::mpsc::TryRecvError::Disconnected) => Some(Err(anyhow!(
                "the file could not be read (its reader stopped)"
            ))),
        }
    }
}

/// Reads `path` and prepares its strokes, telling `step` where it is.
fn load(path: &Path, session: bool, step: &dyn Fn(Phase)) -> anyhow::Result<Loaded> {
    let content = if session {
        let bytes = std::fs::read(path).context("the file cannot be read")?;
        let session = parse_session(&bytes)
            .or_else(|_| load_session(path))
            .map_err(|e| anyhow!("{e}"))?;
        Content::Session(Box::new(session))
    } else {
        let loaded = load_sketch(path)?;
        if loaded.sketch.strokes.is_empty() {
            return Err(anyhow!("it has no strokes to snap to"));
        }
        Content::Drawing {
            sketch: loaded.sketch,
            image: loaded.image,
            warnings: loaded.warnings,
        }
    };
    let sketch = content.sketch();
    step(Phase::Sorting(sketch.strokes.len()));
    let classes = classify_sketch(sketch, &ClassifyOptions::default())
        .into_iter()
        .map(|c| (c.id, c.class))
        .collect();
    step(Phase::Preparing(sketch.strokes.len()));
    let prepared = SnapContext::prepare(sketch);
    Ok(Loaded {
        content,
        classes,
        context: prepared.context,
        merged: prepared.merged.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::{thousands, Phase};

    #[test]
    fn steps_read_in_words_with_thousands_apart() {
        assert_eq!(thousands(7), "7");
        assert_eq!(thousands(2900), "2,900");
        assert_eq!(thousands(1_234_567), "1,234,567");
        assert_eq!(
            Phase::Sorting(2900).text(),
            "sorting 2,900 strokes into ends and outlines"
        );
    }
}
