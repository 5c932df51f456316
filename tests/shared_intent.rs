//! The relations a designer intends on each shared hand-drawn sketch, measured against
//! the relations geosnap infers (issue 17's acceptance), run when
//! `GEOSNAP_SHARED_SKETCHES` names the folder holding the sketches (CI sets it; the test
//! passes with a note when it is unset and fails when it names a missing folder).
//!
//! # The lists
//!
//! Beside each part script `tests/shared_scripts/parts/NAME.script.json` (one step per
//! part, named in step order by `NAME.reference.json`, see `tests/shared_parts.rs`),
//! `NAME.relations.json` lists relations between those parts by the reference's names:
//!
//! - `intended`: what a designer would name as the design's intent, read off the drawing
//!   (never off geosnap's output): a table's legs upright under the top and meeting it,
//!   alike in radius and length; stacked parts on one axis with their touching ends
//!   centred on each other; a stud standing on a brick's face, parallel and coplanar;
//!   tubes sticking out of a ball;
//! - `acceptable`: true in the design and harmless, but nothing a designer would insist
//!   on: what the intended relations imply (touching ends that are concentric and coaxial
//!   are also coplanar), centres collinear along an axis, a post square to a box's other
//!   faces.
//!
//! Anything else is unwanted. Each entry has a `kind` (a [`RelationKind`] as the model file
//! names it), its `parts` (two, or three for `collinear_centers`) and a `why`. A group of
//! alike parts is listed as a chain of pairs (legs 1–2, 2–3, 3–4), not every pair.
//!
//! # Matching
//!
//! Each script runs as a session would ([`common::run_script_document`]); a primitive is
//! named by the reference entry of the step that placed it (`fit.step`). Relations are
//! compared by kind and by the SET of their parts' names; the features a relation uses
//! (which end, which face) are not compared, as the lists name parts, not features.
//!
//! A listed relation is *found* among a set of inferred relations when one of them has its
//! kind and its parts, or, for the kinds that are equivalences, when a chain of them joins
//! its parts: the inferred relations of one kind make classes of parts (union–find), and
//! the listed parts must fall in one class. The classes per kind:
//!
//! | listed kind | joined by inferred |
//! |---|---|
//! | parallel | parallel, coaxial (a shared axis is a shared direction) |
//! | coaxial, concentric, coplanar, same_radius, equal_length | the same kind |
//! | orthogonal, collinear_centers, on_sphere | — (found directly only) |
//!
//! An inferred relation is *wanted* when it is listed (intended or acceptable) directly,
//! or when it is of an equivalence kind and a chain of listed relations (intended ∪
//! acceptable, classes as in the table) joins its parts. One more implication: inference
//! may make a `collinear_centers` of both ends of one part and an end of another (two part
//! names), saying the other's end centre lies on the first part's axis; it is wanted when
//! the two parts are coaxial by the lists (directly or through a chain).
//!
//! # Measures
//!
//! A relation's mode decides how it counts: *hard* is `Mode::Hard`; *enforced or
//! suggested* is every mode but `Mode::Off` (hard, soft, and the medium-confidence
//! suggestions a user has yet to accept); a *suggestion* is any mode that is neither off,
//! hard nor soft. Per sketch and pooled over all sketches:
//!
//! - **recall** ([`RECALL_TARGET`]): of the intended relations whose parts were all placed,
//!   the fraction found among the enforced or suggested relations. Also shown: the same
//!   over ALL intended relations (a relation with a part whose step was skipped counts as
//!   missed) and the fraction found among the hard relations only (over placed parts);
//! - **unwanted hard** ([`UNWANTED_HARD_CEILING`]): of the hard relations, the fraction that
//!   are not wanted; each is listed with its sketch, kind, parts and features;
//! - **suggestions**: how many there are and how many of them are wanted.
//!
//! With `GEOSNAP_INTENT_DETAIL` set, each missed relation is printed with its parts'
//! final poses.
//!
//! The pooled figures are sums over sketches (a sketch with many intended relations, such
//! as the menorah, weighs more), and the targets are asserted on them.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use geosnap::core::model::reading::DrawnEnds;
use geosnap::core::model::{Document, Relation};
use geosnap::core::relation::{Mode, RelationKind};
use serde::Deserialize;

/// The target, asserted: at least this fraction of the intended relations
/// between placed parts is found among the enforced or suggested relations (pooled over
/// all sketches). Met since session 19 (0.90); what is missed is mostly parts whose own
/// snap is off (tubes on the ball whose snapped depths put them 74° apart, cup rims the
/// snap tilts sideways, a stem 13 units off its base's axis).
const RECALL_TARGET: f64 = 0.85;
/// The target: at most this fraction of the hard relations is unwanted (neither
/// intended nor acceptable, directly or through a chain; pooled over all sketches).
const UNWANTED_HARD_CEILING: f64 = 0.03;

/// One relation of a `NAME.relations.json` list.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Listed {
    /// Its kind.
    kind: RelationKind,
    /// The names of its parts, as the reference names them.
    parts: Vec<String>,
    /// Why a designer wants it (read by people only).
    #[allow(dead_code, reason = "documentation for the reader of the list")]
    why: String,
}

/// A `NAME.relations.json` file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Intent {
    /// The sketch's file name.
    sketch: String,
    /// What a designer would name as design intent.
    intended: Vec<Listed>,
    /// True and harmless, but not insisted on.
    acceptable: Vec<Listed>,
}

/// The part of a `NAME.reference.json` entry this test reads.
#[derive(Debug, Deserialize)]
struct ReferencePart {
    /// The part's name.
    name: String,
}

/// The part of a `NAME.reference.json` file this test reads.
#[derive(Debug, Deserialize)]
struct Reference {
    /// The sketch's file name.
    sketch: String,
    /// One entry per script step.
    parts: Vec<ReferencePart>,
}

/// A relation by kind and the set of its parts' names.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Named {
    /// Its kind.
    kind: RelationKind,
    /// Its parts' names.
    parts: BTreeSet<String>,
}

impl Named {
    /// A listed relation by kind and names.
    fn listed(listed: &Listed) -> Self {
        Self {
            kind: listed.kind,
            parts: listed.parts.iter().cloned().collect(),
        }
    }
}

/// The kinds whose inferred relations join the classes of a relation of `kind` (empty for
/// the kinds that are no equivalence).
fn joining(kind: RelationKind) -> &'static [RelationKind] {
    match kind {
        RelationKind::Parallel => &[RelationKind::Parallel, RelationKind::Coaxial],
        RelationKind::Coaxial => &[RelationKind::Coaxial],
        RelationKind::Concentric => &[RelationKind::Concentric],
        RelationKind::Coplanar => &[RelationKind::Coplanar],
        RelationKind::SameRadius => &[RelationKind::SameRadius],
        RelationKind::EqualLength => &[RelationKind::EqualLength],
        RelationKind::Orthogonal | RelationKind::CollinearCenters | RelationKind::OnSphere => &[],
    }
}

/// A set of relations by name, asked whether it holds a relation directly or through a
/// chain.
struct Relations {
    /// The relations themselves.
    direct: BTreeSet<Named>,
    /// Per kind, each part's parent in the union–find over the relations of the kinds
    /// that join that kind's classes.
    classes: BTreeMap<RelationKind, BTreeMap<String, String>>,
}

impl Relations {
    /// The classes of `relations`.
    fn new<'a>(relations: impl IntoIterator<Item = &'a Named>) -> Self {
        let direct: BTreeSet<Named> = relations.into_iter().cloned().collect();
        let mut classes = BTreeMap::new();
        for kind in RelationKind::ALL {
            let joined_by = joining(kind);
            if joined_by.is_empty() {
                continue;
            }
            let mut parent = BTreeMap::new();
            for r in direct.iter().filter(|r| joined_by.contains(&r.kind)) {
                let mut parts = r.parts.iter();
                let Some(first) = parts.next() else {
                    continue;
                };
                let root = find(&mut parent, first);
                for part in parts {
                    let other = find(&mut parent, part);
                    if other != root {
                        parent.insert(other, root.clone());
                    }
                }
            }
            classes.insert(kind, parent);
        }
        Self { direct, classes }
    }

    /// Whether `relation` is among these directly or, for an equivalence kind, through a
    /// chain.
    fn holds(&self, relation: &Named) -> bool {
        if self.direct.contains(relation) {
            return true;
        }
        if relation.kind == RelationKind::CollinearCenters && relation.parts.len() == 2 {
            // Both ends of one part and an end of another: that end's centre lies on the
            // first part's axis, which a shared axis implies.
            return self.holds(&Named {
                kind: RelationKind::Coaxial,
                parts: relation.parts.clone(),
            });
        }
        let Some(parent) = self.classes.get(&relation.kind) else {
            return false;
        };
        let mut parent = parent.clone();
        let roots: BTreeSet<String> = relation
            .parts
            .iter()
            .map(|p| find(&mut parent, p))
            .collect();
        roots.len() == 1
    }
}

/// The root of `part`'s class (a part never seen is its own class).
fn find(parent: &mut BTreeMap<String, String>, part: &str) -> String {
    let mut at = part.to_owned();
    while let Some(up) = parent.get(&at) {
        if *up == at {
            break;
        }
        at.clone_from(up);
    }
    parent.entry(part.to_owned()).or_insert_with(|| at.clone());
    at
}

/// An inferred relation by name, with what the report shows of it.
struct Inferred {
    /// Its kind and parts' names.
    named: Named,
    /// Its mode.
    mode: Mode,
    /// Its parts' names in member order, with the features used.
    shown: String,
}

/// Counts for one sketch (or summed over all), from which the fractions come.
#[derive(Clone, Copy, Debug, Default)]
struct Counts {
    /// Intended relations.
    intended: usize,
    /// … whose parts were all placed.
    placed: usize,
    /// … found among the enforced or suggested relations.
    found: usize,
    /// … found among the hard relations.
    found_hard: usize,
    /// Hard relations.
    hard: usize,
    /// … not wanted.
    unwanted_hard: usize,
    /// Suggestions.
    suggested: usize,
    /// … wanted.
    suggested_wanted: usize,
}

impl Counts {
    /// The sum of two counts.
    fn add(self, other: Self) -> Self {
        Self {
            intended: self.intended + other.intended,
            placed: self.placed + other.placed,
            found: self.found + other.found,
            found_hard: self.found_hard + other.found_hard,
            hard: self.hard + other.hard,
            unwanted_hard: self.unwanted_hard + other.unwanted_hard,
            suggested: self.suggested + other.suggested,
            suggested_wanted: self.suggested_wanted + other.suggested_wanted,
        }
    }

    /// Recall over the intended relations between placed parts (1 when there are none).
    fn recall(&self) -> f64 {
        fraction(self.found, self.placed, 1.0)
    }

    /// Recall over all intended relations (1 when there are none).
    fn recall_all(&self) -> f64 {
        fraction(self.found, self.intended, 1.0)
    }

    /// Recall by the hard relations over those between placed parts.
    fn recall_hard(&self) -> f64 {
        fraction(self.found_hard, self.placed, 1.0)
    }

    /// The fraction of the hard relations that are unwanted (0 when there are none).
    fn unwanted(&self) -> f64 {
        fraction(self.unwanted_hard, self.hard, 0.0)
    }
}

/// `part / whole`, or `empty` when `whole` is 0.
fn fraction(part: usize, whole: usize, empty: f64) -> f64 {
    let as_f64 = |n: usize| f64::from(u32::try_from(n).expect("a small count"));
    if whole == 0 {
        empty
    } else {
        as_f64(part) / as_f64(whole)
    }
}

/// The folder of the part scripts and lists.
fn parts_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/shared_scripts/parts")
}

/// The names of the sketches with a `.relations.json`, sorted.
fn listed_sketches() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(parts_dir())
        .expect("the parts folder is readable")
        .filter_map(Result::ok)
        .filter_map(|e| {
            e.file_name()
                .to_str()?
                .strip_suffix(".relations.json")
                .map(str::to_owned)
        })
        .collect();
    names.sort();
    names
}

/// Reads a JSON file of the parts folder.
fn read_json<T: for<'de> Deserialize<'de>>(file: &str) -> T {
    let path = parts_dir().join(file);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{} is readable: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{} parses: {e}", path.display()))
}

/// A sketch's list and reference names, checked against each other.
fn load(name: &str) -> (Intent, Vec<String>) {
    let intent: Intent = read_json(&format!("{name}.relations.json"));
    let reference: Reference = read_json(&format!("{name}.reference.json"));
    assert_eq!(intent.sketch, reference.sketch, "{name}: the lists' sketch");
    let names: Vec<String> = reference.parts.into_iter().map(|p| p.name).collect();
    let unique: BTreeSet<&String> = names.iter().collect();
    assert_eq!(unique.len(), names.len(), "{name}: reference names repeat");
    for listed in intent.intended.iter().chain(&intent.acceptable) {
        let parts: BTreeSet<&String> = listed.parts.iter().collect();
        assert!(
            listed.parts.len() == listed.kind.arity() && parts.len() == listed.parts.len(),
            "{name}: a {} relation needs {} different parts: {:?}",
            listed.kind.name(),
            listed.kind.arity(),
            listed.parts
        );
        for part in &listed.parts {
            assert!(names.contains(part), "{name}: no part is named {part:?}");
        }
    }
    (intent, names)
}

/// The document's relations by name: a primitive is named by the reference entry of the
/// step that placed it (or `#id` when no step did).
fn inferred(document: &Document, names: &[String]) -> Vec<Inferred> {
    let name_of: BTreeMap<_, String> = document
        .primitives()
        .map(|(id, placed)| {
            let name = placed
                .fit
                .step
                .and_then(|s| names.get(s).cloned())
                .unwrap_or_else(|| format!("#{}", id.0));
            (id, name)
        })
        .collect();
    document
        .relations()
        .iter()
        .map(|r: &Relation| {
            let parts: Vec<String> = r.members.iter().map(|m| name_of[m].clone()).collect();
            let mut shown = parts.join(" / ");
            if !r.features.is_empty() {
                let _ = write!(shown, " {:?}", r.features);
            }
            Inferred {
                named: Named {
                    kind: r.kind,
                    parts: parts.into_iter().collect(),
                },
                mode: r.mode,
                shown,
            }
        })
        .collect()
}

/// What the report lists of one sketch besides its counts.
#[derive(Default)]
struct Listing {
    /// A line per unwanted hard relation.
    unwanted: Vec<String>,
    /// A line per intended relation between placed parts not found (enforced or
    /// suggested).
    missed: Vec<String>,
    /// A line per part whose final pose is the mirror reading its drawn ends contradict
    /// (see [`against_the_drawing`]).
    against: Vec<String>,
}

/// The parts of `document` that end in a depth-mirror reading their strokes contradict
/// more than the other: the end the pose turns to the viewer is drawn as a half, or the
/// one it turns away is drawn whole while the other is a half
/// (`geosnap::core::model::reading`). The release must never flip a part into such a
/// reading for a relation (issue 17: no mirror flip that worsens a part's fit).
fn against_the_drawing(document: &Document, names: &[String]) -> Vec<String> {
    document
        .primitives()
        .filter_map(|(id, placed)| {
            let record = document.snap_record(id)?;
            let p = &placed.primitive;
            let ends = DrawnEnds::of(p, &record.assignment);
            (ends.agreement(p) < ends.agreement(&p.mirrored_in_depth())).then(|| {
                let name = placed.fit.step.and_then(|s| names.get(s));
                format!("{} ({ends:?})", name.map_or("?", String::as_str))
            })
        })
        .collect()
}

/// Measures one sketch; returns its counts and what the report lists of it.
fn measure(name: &str, dir: &Path) -> (Counts, Listing) {
    let (intent, names) = load(name);
    let script = parts_dir().join(format!("{name}.script.json"));
    let (_, failures, document) = common::run_script_document(&script, Some(dir));
    for failure in &failures {
        eprintln!("{name}: note: {failure}");
    }
    let placed: BTreeSet<String> = document
        .primitives()
        .filter_map(|(_, p)| p.fit.step.and_then(|s| names.get(s).cloned()))
        .collect();
    let relations = inferred(&document, &names);
    let active = Relations::new(
        relations
            .iter()
            .filter(|r| r.mode != Mode::Off)
            .map(|r| &r.named),
    );
    let hard = Relations::new(
        relations
            .iter()
            .filter(|r| r.mode == Mode::Hard)
            .map(|r| &r.named),
    );
    let wanted = Relations::new(
        intent
            .intended
            .iter()
            .chain(&intent.acceptable)
            .map(Named::listed)
            .collect::<Vec<_>>()
            .iter(),
    );
    let mut listing = Listing {
        against: against_the_drawing(&document, &names)
            .into_iter()
            .map(|part| format!("{name}: {part}"))
            .collect(),
        ..Listing::default()
    };
    let mut counts = Counts {
        intended: intent.intended.len(),
        ..Counts::default()
    };
    for listed in &intent.intended {
        if !listed.parts.iter().all(|p| placed.contains(p)) {
            continue;
        }
        counts.placed += 1;
        let named = Named::listed(listed);
        let found = active.holds(&named);
        counts.found += usize::from(found);
        counts.found_hard += usize::from(hard.holds(&named));
        if !found {
            let mut line = format!(
                "{name}: {} {}",
                listed.kind.name(),
                listed.parts.join(" / ")
            );
            if std::env::var_os("GEOSNAP_INTENT_DETAIL").is_some() {
                for part in &listed.parts {
                    for (_, placed) in document.primitives() {
                        if placed.fit.step.and_then(|s| names.get(s)) == Some(part) {
                            let _ = write!(line, "\n      {part}: {:.2?}", placed.primitive);
                        }
                    }
                }
            }
            listing.missed.push(line);
        }
    }
    for r in &relations {
        let is_wanted = wanted.holds(&r.named);
        if r.mode == Mode::Hard {
            counts.hard += 1;
            if !is_wanted {
                counts.unwanted_hard += 1;
                listing
                    .unwanted
                    .push(format!("{name}: {} {}", r.named.kind.name(), r.shown));
            }
        } else if r.mode != Mode::Off && r.mode != Mode::Soft {
            counts.suggested += 1;
            counts.suggested_wanted += usize::from(is_wanted);
        }
    }
    (counts, listing)
}

/// One row of the table.
fn row(label: &str, c: &Counts) -> String {
    format!(
        "{label:<18} {:>4} {:>4} {:>4} {:>6.2} {:>6.2} {:>6.2} {:>4} {:>4} {:>6.1} {:>4} {:>4}",
        c.intended,
        c.placed,
        c.found,
        c.recall(),
        c.recall_all(),
        c.recall_hard(),
        c.hard,
        c.unwanted_hard,
        100.0 * c.unwanted(),
        c.suggested,
        c.suggested_wanted
    )
}

#[test]
fn inferred_relations_match_the_designers_intent() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    let sketches = listed_sketches();
    assert!(
        !sketches.is_empty(),
        "no .relations.json in the parts folder"
    );
    let mut table = String::from(
        "sketch              int  pla  fnd recall    all   hard hard unwt unwt %  sug  s.ok\n",
    );
    let mut total = Counts::default();
    let mut all = Listing::default();
    for name in &sketches {
        let (counts, listing) = measure(name, &dir);
        let _ = writeln!(table, "{}", row(name, &counts));
        total = total.add(counts);
        all.unwanted.extend(listing.unwanted);
        all.missed.extend(listing.missed);
        all.against.extend(listing.against);
    }
    let _ = writeln!(table, "{}", row("overall", &total));
    eprintln!(
        "\nint: intended, pla: … between placed parts, fnd: … found (enforced or suggested);\n\
         recall over placed parts, over all, by hard relations only; hard relations and the\n\
         unwanted ones; suggestions and the wanted ones\n\n{table}"
    );
    eprintln!("intended relations not found ({}):", all.missed.len());
    for line in &all.missed {
        eprintln!("  {line}");
    }
    eprintln!("unwanted hard relations ({}):", all.unwanted.len());
    for line in &all.unwanted {
        eprintln!("  {line}");
    }
    eprintln!(
        "parts in the mirror reading their drawn ends contradict ({}):",
        all.against.len()
    );
    for line in &all.against {
        eprintln!("  {line}");
    }
    eprintln!(
        "recall {:.3}: issue 17's target {RECALL_TARGET} {}",
        total.recall(),
        if total.recall() >= RECALL_TARGET {
            "met"
        } else {
            "NOT met"
        }
    );
    assert!(
        total.recall() >= RECALL_TARGET,
        "recall {:.3} is below issue 17's target {RECALL_TARGET}",
        total.recall()
    );
    assert!(
        total.unwanted() <= UNWANTED_HARD_CEILING,
        "{:.1} % of the hard relations are unwanted, above the ceiling of {:.1} %",
        100.0 * total.unwanted(),
        100.0 * UNWANTED_HARD_CEILING
    );
}
