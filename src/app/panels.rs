//! The menu bar, the palette and tools, the relations / properties / messages panels
//! and the settings window.

use std::collections::BTreeMap;

use egui::{Color32, RichText, Ui};

use super::files::{After, PathAction};
use super::help::{keys_text, Action};
use super::{mode_name, words, GeosnapApp, Tool};
use crate::core::model::{PrimitiveId, Quantity};
use crate::core::primitive::{Primitive, PrimitiveKind};
use crate::core::relation::{Mode, RelationKind};

/// The panels' own state: the dimension values being typed, the part being renamed,
/// and whether the settings window is open.
#[derive(Debug, Default)]
pub(crate) struct Panels {
    /// Typed dimension values being edited in the properties panel, by part and
    /// quantity.
    typed: BTreeMap<String, String>,
    /// The relation being made by hand.
    relate: Relate,
    /// The part whose name is being typed in the outliner.
    rename: Option<Rename>,
    show_settings: bool,
}

/// A name being typed in the outliner: Enter (or a click elsewhere) keeps it, Esc
/// leaves the name as it was.
#[derive(Debug)]
struct Rename {
    id: PrimitiveId,
    text: String,
    /// Whether the field is still to take the keyboard (its first frame).
    focus: bool,
}

impl Panels {
    /// The part being renamed, with the name typed so far.
    pub(crate) fn renaming(&self) -> Option<(PrimitiveId, &str)> {
        self.rename.as_ref().map(|r| (r.id, r.text.as_str()))
    }
}

/// The label of the field a part's name is typed in (its accessible name too).
pub(crate) const NAME_FIELD: &str = "Name";

impl GeosnapApp {
    #[expect(clippy::too_many_lines, reason = "one menu bar, read top to bottom")]
    pub(crate) fn menu_bar(&mut self, ui: &mut Ui) {
        egui::Panel::top("menu")
            .frame(super::unfilled(3.0))
            .show(ui, |ui| {
                egui::MenuBar::new().ui(ui, |ui| {
                    let ctx = ui.ctx().clone();
                    ui.menu_button("File", |ui| {
                        if ui
                            .add(
                                egui::Button::new("New")
                                    .shortcut_text(keys_text(&ctx, Action::New)),
                            )
                            .clicked()
                        {
                            self.request(&ctx, After::New);
                        }
                        if ui
                            .add(
                                egui::Button::new("Open…")
                                    .shortcut_text(keys_text(&ctx, Action::Open)),
                            )
                            .clicked()
                        {
                            self.request(&ctx, After::Open(None));
                        }
                        ui.menu_button("Open recent", |ui| {
                            if self.files.recent().is_empty() {
                                ui.label("(none)");
                            }
                            for path in self.files.recent().to_vec() {
                                if ui.button(path.display().to_string()).clicked() {
                                    self.request(&ctx, After::Open(Some(path)));
                                }
                            }
                        });
                        if ui.button("Open path…").clicked() {
                            self.ask_path(PathAction::Open);
                        }
                        ui.separator();
                        if ui
                            .add(
                                egui::Button::new("Save")
                                    .shortcut_text(keys_text(&ctx, Action::Save)),
                            )
                            .clicked()
                        {
                            self.save(&ctx);
                        }
                        if ui
                            .add(
                                egui::Button::new("Save as…")
                                    .shortcut_text(keys_text(&ctx, Action::SaveAs)),
                            )
                            .clicked()
                        {
                            self.save_as(&ctx);
                        }
                        if ui.button("Save to path…").clicked() {
                            self.ask_path(PathAction::SaveAs);
                        }
                        ui.separator();
                        if ui
                            .add(
                                egui::Button::new("Export glTF…")
                                    .shortcut_text(keys_text(&ctx, Action::Export)),
                            )
                            .clicked()
                        {
                            self.export_dialog();
                        }
                        if ui.button("Export to path…").clicked() {
                            self.ask_path(PathAction::Export);
                        }
                        ui.separator();
                        if ui.button("Quit").clicked() {
                            self.request(&ctx, After::Quit);
                        }
                    });
                    ui.menu_button("Edit", |ui| {
                        let undo = self.editor.undo_label().map(|l| format!("Undo {l}"));
                        if ui
                            .add_enabled(
                                undo.is_some() && !self.busy(),
                                egui::Button::new(undo.unwrap_or_else(|| "Undo".into()))
                                    .shortcut_text(keys_text(&ctx, Action::Undo)),
                            )
                            .clicked()
                        {
                            self.undo();
                        }
                        let redo = self.editor.redo_label().map(|l| format!("Redo {l}"));
                        if ui
                            .add_enabled(
                                redo.is_some() && !self.busy(),
                                egui::Button::new(redo.unwrap_or_else(|| "Redo".into()))
                                    .shortcut_text(keys_text(&ctx, Action::Redo)),
                            )
                            .clicked()
                        {
                            self.redo();
                        }
                        ui.separator();
                        let selected = self.selection.is_some() && !self.busy();
                        if ui
                            .add_enabled(
                                selected,
                                egui::Button::new("Duplicate")
                                    .shortcut_text(keys_text(&ctx, Action::Duplicate)),
                            )
                            .clicked()
                        {
                            self.duplicate_selected();
                        }
                        if ui
                            .add_enabled(
                                selected,
                                egui::Button::new("Delete")
                                    .shortcut_text(keys_text(&ctx, Action::Delete)),
                            )
                            .clicked()
                        {
                            self.delete_selected();
                        }
                        if ui
                            .add_enabled(
                                selected,
                                egui::Button::new("Rename…")
                                    .shortcut_text(keys_text(&ctx, Action::Rename)),
                            )
                            .clicked()
                        {
                            if let Some(id) = self.selection {
                                self.start_rename(id);
                            }
                        }
                        ui.separator();
                        if ui.button("Settings…").clicked() {
                            self.panels.show_settings = true;
                        }
                    });
                    ui.menu_button("View", |ui| {
                        for (text, action) in [
                            ("Fit", Action::Fit),
                            ("View from drawing", Action::HomeView),
                            ("Front", Action::FrontView),
                            ("Top", Action::TopView),
                            ("Side", Action::SideView),
                            ("Isometric", Action::IsometricView),
                        ] {
                            let button =
                                egui::Button::new(text).shortcut_text(keys_text(&ctx, action));
                            if ui.add(button).clicked() {
                                self.run_action(&ctx, action);
                            }
                        }
                        ui.separator();
                        ui.add(
                            egui::Slider::new(self.canvas.image_mut().opacity_mut(), 0.0..=1.0)
                                .text("Image opacity"),
                        );
                        ui.checkbox(&mut self.status.developer, "Developer info")
                            .on_hover_text(
                                "Show solver figures (rounds, residuals) and frame and snap \
                                 times",
                            );
                    });
                    ui.menu_button("Help", |ui| {
                        let button = egui::Button::new("Keyboard shortcuts")
                            .shortcut_text(keys_text(&ctx, Action::Help));
                        if ui.add(button).clicked() {
                            self.help.shortcuts_open = true;
                        }
                        if ui.button("Show the welcome hint").clicked() {
                            self.help.first_run_hint = true;
                        }
                    });
                });
            });
    }

    pub(crate) fn palette(&mut self, ui: &mut Ui) {
        egui::Panel::left("palette")
            .frame(super::unfilled(6.0))
            .resizable(false)
            .exact_size(150.0)
            .show(ui, |ui| {
                ui.add_space(4.0);
                ui.heading("Primitives");
                ui.label(RichText::new("Drag onto the drawing").weak());
                for kind in PrimitiveKind::ALL {
                    let tip = words::kind_long(kind);
                    let tip = format!("{}{}", tip[..1].to_uppercase(), &tip[1..]);
                    let button = egui::Button::new(words::kind_title(kind))
                        .min_size(egui::vec2(ui.available_width(), 28.0))
                        .sense(egui::Sense::click_and_drag());
                    let response = ui.add_enabled(!self.busy(), button).on_hover_text(tip);
                    if response.drag_started() {
                        self.begin_drag(kind);
                    }
                }
                ui.add_space(12.0);
                ui.heading("Tools");
                for (tool, label, tip) in [
                    (
                        Tool::Select,
                        "Select  V",
                        "Click a part to select it; drag it to move and re-snap",
                    ),
                    (
                        Tool::Draw,
                        "Draw  B",
                        "Draw strokes with the mouse or a pen",
                    ),
                    (
                        Tool::Erase,
                        "Erase  E",
                        "Click or drag over strokes to erase them",
                    ),
                    (
                        Tool::Reclassify,
                        "Reclassify  C",
                        "Click a stroke to switch it between feature (blue) and silhouette (black)",
                    ),
                ] {
                    ui.selectable_value(self.canvas.tool_mut(), tool, label)
                        .on_hover_text(tip);
                }
                ui.add_space(12.0);
                ui.heading("Strokes");
                for (color, label) in [
                    (Color32::from_rgb(40, 110, 220), "ends (feature)"),
                    (Color32::from_rgb(45, 45, 50), "outlines (sides)"),
                ] {
                    ui.horizontal(|ui| {
                        let (rect, _) =
                            ui.allocate_exact_size(egui::vec2(22.0, 12.0), egui::Sense::hover());
                        ui.painter().line_segment(
                            [rect.left_center(), rect.right_center()],
                            egui::Stroke::new(2.5, color),
                        );
                        ui.label(label);
                    });
                }
                if self.canvas.image().is_shown() {
                    ui.add_space(12.0);
                    ui.label("Image opacity");
                    ui.add(
                        egui::Slider::new(self.canvas.image_mut().opacity_mut(), 0.0..=1.0)
                            .show_value(false),
                    );
                }
            });
    }

    /// Properties and relations above, scrolling together however many relations there
    /// are; the messages below in a band of their own (newest first, with their own
    /// scroll bar), so they are never pushed out of the window.
    pub(crate) fn side_panels(&mut self, ui: &mut Ui) {
        let height = ui.available_height();
        egui::Panel::bottom("messages")
            .frame(super::unfilled(2.0))
            .resizable(true)
            .default_size(height * 0.3)
            .min_size(80.0)
            .max_size(height * 0.8)
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.strong("Messages");
                    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                        if ui.button("Clear").clicked() {
                            self.status.clear();
                        }
                    });
                });
                egui::ScrollArea::vertical()
                    .id_salt("messages_scroll")
                    .auto_shrink([false, false])
                    .show(ui, |ui| self.status.messages_ui(ui));
            });
        egui::CentralPanel::default()
            .frame(super::unfilled(0.0))
            .show(ui, |ui| {
                egui::ScrollArea::vertical()
                    .id_salt("inspector_scroll")
                    .auto_shrink([false, false])
                    .show(ui, |ui| {
                        egui::CollapsingHeader::new(format!(
                            "Parts ({})",
                            self.editor.document().len()
                        ))
                        .default_open(true)
                        // A part being renamed shows its name field.
                        .open(self.panels.rename.is_some().then_some(true))
                        .show(ui, |ui| self.outliner(ui));
                        egui::CollapsingHeader::new("Properties")
                            .default_open(true)
                            .show(ui, |ui| self.properties(ui));
                        egui::CollapsingHeader::new(format!(
                            "Relations ({})",
                            self.editor.document().relations().len()
                        ))
                        .default_open(true)
                        .show(ui, |ui| self.relations(ui));
                        egui::CollapsingHeader::new("Relate two parts by hand")
                            .default_open(false)
                            .show(ui, |ui| self.relate_ui(ui));
                    });
            });
    }

    /// Starts typing a new name for part `id` in the outliner (F2, a double-click, or
    /// Rename… in its context menu).
    pub(crate) fn start_rename(&mut self, id: PrimitiveId) {
        if self.editor.document().get(id).is_none() {
            return;
        }
        self.selection = Some(id);
        self.panels.rename = Some(Rename {
            id,
            text: self
                .editor
                .document()
                .name(id)
                .unwrap_or_default()
                .to_owned(),
            focus: true,
        });
    }

    /// The field a part's new name is typed in, in its outliner row. Enter, or a click
    /// elsewhere, keeps the name; Esc leaves it as it was.
    fn rename_field(&mut self, ui: &mut Ui, id: PrimitiveId, placeholder: &str) {
        let Some(rename) = self.panels.rename.as_mut().filter(|r| r.id == id) else {
            return;
        };
        let edit_id = ui.make_persistent_id(("rename", id.0));
        let field = egui::TextEdit::singleline(&mut rename.text)
            .id(edit_id)
            .hint_text(placeholder)
            .char_limit(crate::core::model::MAX_NAME_CHARS)
            .desired_width(ui.available_width().clamp(80.0, 220.0));
        let label = ui.label(NAME_FIELD).id;
        let response = ui.add(field).labelled_by(label).on_hover_text(
            "The part's name: Enter keeps it, Esc leaves the name as it was; an empty \
             name gives the part back its kind and number",
        );
        if rename.focus {
            rename.focus = false;
            response.request_focus();
            response.scroll_to_me(None);
            // The whole name selected, so typing replaces it.
            if let Some(mut state) = egui::TextEdit::load_state(ui.ctx(), edit_id) {
                state.cursor.set_char_range(Some(
                    egui::text_selection::CCursorRange::select_all_str(&rename.text),
                ));
                egui::TextEdit::store_state(ui.ctx(), edit_id, state);
            }
            return;
        }
        // The field's own focus, not `has_focus`, which also asks that the window have
        // the system's focus: switching to another window keeps the name being typed.
        let focused = ui.memory(|m| m.has_focus(response.id));
        if response.lost_focus() || !focused {
            let cancelled = ui.input(|i| i.key_pressed(egui::Key::Escape));
            let text = rename.text.clone();
            if cancelled || self.rename(id, &text) {
                self.panels.rename = None;
            } else {
                // Busy: the name stays typed, to be kept once the solve is over.
                response.request_focus();
            }
        }
    }

    /// The parts, one a row: shown or hidden, its name (click selects it, double-click,
    /// F2 or its context menu renames it) with how its snap was judged, and a button
    /// that deletes it.
    fn outliner(&mut self, ui: &mut Ui) {
        let document = self.editor.document();
        if self
            .panels
            .rename
            .as_ref()
            .is_some_and(|r| document.get(r.id).is_none())
        {
            self.panels.rename = None;
        }
        if document.is_empty() {
            ui.label(RichText::new("No parts yet: drag one from the palette.").weak());
            return;
        }
        // Each row's part, name, kind and id, and how it was placed.
        let rows: Vec<(PrimitiveId, String, String, &str)> = document
            .primitives()
            .map(|(id, placed)| {
                let state = match (placed.fit.strokes.is_empty(), placed.fit.verdict) {
                    (true, _) => " · placed freely",
                    (false, Some(crate::core::snap::Verdict::Doubtful)) => " · doubtful",
                    _ => "",
                };
                let kind_id = words::kind_id(placed.primitive.kind(), id);
                (id, words::part_name(document, id), kind_id, state)
            })
            .collect();
        let busy = self.busy();
        let mut select = None;
        let mut toggle = None;
        let mut delete = None;
        let mut rename = None;
        for (index, (id, name, kind_id, state)) in rows.into_iter().enumerate() {
            ui.horizontal(|ui| {
                let mut shown = !self.hidden.contains(&id);
                if ui
                    .add(egui::Checkbox::without_text(&mut shown))
                    .on_hover_text("Show or hide it on the drawing and in the 3D view")
                    .changed()
                {
                    toggle = Some(id);
                }
                let (swatch, _) =
                    ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
                ui.painter()
                    .rect_filled(swatch, 2.0, super::view3d::part_color(index));
                if self.panels.rename.as_ref().is_some_and(|r| r.id == id) {
                    self.rename_field(ui, id, &kind_id);
                    return;
                }
                let selected = self.selection == Some(id);
                let row = ui.selectable_label(selected, format!("{name}{state}"));
                let hover = if name == kind_id {
                    "Click selects it; double-click or F2 names it".to_owned()
                } else {
                    format!("{kind_id}. Click selects it; double-click or F2 renames it")
                };
                let row = row.on_hover_text(hover);
                if row.clicked() {
                    select = Some(id);
                }
                if row.double_clicked() {
                    rename = Some(id);
                }
                row.context_menu(|ui| {
                    let item = egui::Button::new("Rename…")
                        .shortcut_text(keys_text(ui.ctx(), Action::Rename));
                    if ui.add(item).clicked() {
                        rename = Some(id);
                        ui.close();
                    }
                    if ui.add_enabled(!busy, egui::Button::new("Remove")).clicked() {
                        delete = Some(id);
                        ui.close();
                    }
                });
                if ui
                    .add_enabled(!busy, egui::Button::new("Remove").small())
                    .on_hover_text(format!("Delete {name}"))
                    .clicked()
                {
                    delete = Some(id);
                }
            });
        }
        if let Some(id) = select {
            self.selection = Some(id);
        }
        if let Some(id) = toggle {
            if !self.hidden.remove(&id) {
                self.hidden.insert(id);
            }
        }
        if let Some(id) = delete {
            self.selection = Some(id);
            self.delete_selected();
        }
        if let Some(id) = rename {
            self.start_rename(id);
        }
    }

    /// Makes a relation by hand: two parts (the first is the selected one), the feature
    /// of each (or the kind's usual one), the kind; added as a hard relation and solved.
    fn relate_ui(&mut self, ui: &mut Ui) {
        let document = self.editor.document();
        if document.len() < 2 {
            ui.label(RichText::new("Place two parts to relate them.").weak());
            return;
        }
        let ids: Vec<PrimitiveId> = document.primitives().map(|(id, _)| id).collect();
        let relate = &mut self.panels.relate;
        if relate.parts[0].is_none_or(|id| document.get(id).is_none()) {
            relate.parts[0] = self.selection.or(ids.first().copied());
        }
        if relate.parts[1]
            .is_none_or(|id| document.get(id).is_none() || Some(id) == relate.parts[0])
        {
            relate.parts[1] = ids.iter().copied().find(|id| Some(*id) != relate.parts[0]);
        }
        egui::Grid::new("relate").num_columns(2).show(ui, |ui| {
            for (k, which) in ["First part", "Second part"].into_iter().enumerate() {
                let label = ui.label(which).id;
                ui.horizontal(|ui| {
                    let name = |id: Option<PrimitiveId>| {
                        id.map_or_else(String::new, |id| words::part_name(document, id))
                    };
                    let before = relate.parts[k];
                    egui::ComboBox::from_id_salt(("relate_part", k))
                        .selected_text(name(relate.parts[k]))
                        .show_ui(ui, |ui| {
                            for id in &ids {
                                ui.selectable_value(
                                    &mut relate.parts[k],
                                    Some(*id),
                                    name(Some(*id)),
                                );
                            }
                        })
                        .response
                        .labelled_by(label);
                    if relate.parts[k] != before {
                        relate.features[k] = None;
                    }
                    let features = relate.parts[k]
                        .and_then(|id| document.get(id))
                        .map(|p| p.primitive.features())
                        .unwrap_or_default();
                    if !features.is_empty() {
                        let feature_name = |f: Option<crate::core::primitive::Feature>| {
                            f.map_or("usual feature", crate::core::primitive::Feature::name)
                        };
                        egui::ComboBox::from_id_salt(("relate_feature", k))
                            .selected_text(feature_name(relate.features[k]))
                            .show_ui(ui, |ui| {
                                ui.selectable_value(&mut relate.features[k], None, "usual feature");
                                for f in features {
                                    ui.selectable_value(
                                        &mut relate.features[k],
                                        Some(*f),
                                        f.name(),
                                    );
                                }
                            });
                    }
                });
                ui.end_row();
                if k == 0 {
                    let label = ui.label("Relation").id;
                    egui::ComboBox::from_id_salt("relate_kind")
                        .selected_text(words::relation_kind_name(relate.kind))
                        .show_ui(ui, |ui| {
                            for kind in RelationKind::ALL.into_iter().filter(|k| k.arity() == 2) {
                                ui.selectable_value(
                                    &mut relate.kind,
                                    kind,
                                    words::relation_kind_name(kind),
                                );
                            }
                        })
                        .response
                        .labelled_by(label);
                    ui.end_row();
                }
            }
        });
        let add = ui
            .add_enabled(!self.busy(), egui::Button::new("Add relation"))
            .on_hover_text("Add it as a hard relation and solve the two parts");
        if add.clicked() {
            self.add_relation_by_hand();
        }
    }

    /// Adds the relation of the "relate by hand" section, hard, and solves its parts.
    fn add_relation_by_hand(&mut self) {
        let relate = &self.panels.relate;
        let (Some(a), Some(b)) = (relate.parts[0], relate.parts[1]) else {
            return;
        };
        let kind = relate.kind;
        let features = relate.features.to_vec();
        let mut document = self.editor.document().clone();
        let relation = crate::core::model::Relation::new(kind, vec![a, b], features, Mode::Hard);
        match document.add_relation(relation) {
            Ok(id) => {
                let sentence = document
                    .relation(id)
                    .map(|r| words::relation_sentence(&document, r))
                    .unwrap_or_default();
                self.resolve_in_background(
                    &format!("Relate by hand: {sentence}"),
                    document,
                    Some(vec![a, b]),
                );
            }
            Err(error) => self.warn(format!("That relation cannot be made: {error}.")),
        }
    }

    fn relations(&mut self, ui: &mut Ui) {
        self.hovered_relation = None;
        if self.editor.document().relations().is_empty() {
            ui.label(RichText::new("Relations appear when a part is dropped near others.").weak());
            return;
        }
        let mut change = None;
        let mut delete = None;
        let suggested = self
            .editor
            .document()
            .relations()
            .iter()
            .filter(|r| r.mode == Mode::Suggested)
            .count();
        let mut accept_all = false;
        if suggested > 0 {
            ui.horizontal(|ui| {
                ui.label(
                    RichText::new(format!(
                        "{suggested} suggested (not enforced until accepted)"
                    ))
                    .color(SUGGESTED),
                );
                accept_all = ui
                    .add_enabled(!self.busy(), egui::Button::new("Accept all"))
                    .on_hover_text("Make every suggested relation hard and solve the model")
                    .clicked();
            });
        }
        let busy = self.busy();
        let mut hovered = None;
        let document = self.editor.document();
        for (index, (id, relation)) in document.relations_with_ids().enumerate() {
            let text = RichText::new(words::relation_sentence(document, relation));
            let text = match relation.mode {
                Mode::Off => text.strikethrough().weak(),
                Mode::Suggested => text.italics().color(SUGGESTED),
                Mode::Hard | Mode::Soft => text,
            };
            let why = why_inferred(relation);
            let r1 = ui.add(egui::Label::new(text).wrap()).on_hover_text(&why);
            let (r3, r4) = ui.horizontal(|ui| {
                ui.add_space(12.0);
                if relation.mode == Mode::Suggested {
                    let accept = ui
                        .add_enabled(!busy, egui::Button::new("Accept"))
                        .on_hover_text(format!("Make relation {index} hard and solve\n{why}"));
                    if accept.clicked() {
                        change = Some((id, Mode::Hard));
                    }
                    let reject = ui
                        .add_enabled(!busy, egui::Button::new("Reject"))
                        .on_hover_text(format!("Remove suggested relation {index}"));
                    if reject.clicked() {
                        delete = Some(id);
                    }
                    (accept, reject)
                } else {
                    let mut mode = relation.mode;
                    let r3 = egui::ComboBox::from_id_salt(("mode", index))
                        .width(64.0)
                        .selected_text(mode_name(mode))
                        .show_ui(ui, |ui| {
                            for m in [Mode::Hard, Mode::Soft, Mode::Off] {
                                ui.selectable_value(&mut mode, m, mode_name(m));
                            }
                        })
                        .response
                        .on_hover_text(format!("Mode of relation {index}: hard (a constraint), soft (a weighted term) or off"));
                    if mode != relation.mode {
                        change = Some((id, mode));
                    }
                    let r4 = ui.add_enabled(!busy, egui::Button::new("Delete")).on_hover_text(format!("Delete relation {index}"));
                    if r4.clicked() {
                        delete = Some(id);
                    }
                    (r3, r4)
                }
                }).inner;
            if r1.hovered() || r3.hovered() || r4.hovered() {
                hovered = Some(id);
            }
            ui.separator();
        }
        self.hovered_relation = hovered;
        if accept_all {
            self.accept_all_suggestions();
        }
        if let Some((id, mode)) = change {
            self.set_relation_mode(id, mode);
        }
        if let Some(id) = delete {
            self.editor.delete_relation(id);
        }
    }

    #[expect(clippy::too_many_lines, reason = "one panel, read top to bottom")]
    fn properties(&mut self, ui: &mut Ui) {
        let unit = self.unit();
        let Some(id) = self.selection else {
            ui.label(RichText::new("Select a part to see and set its dimensions.").weak());
            return;
        };
        let Some(placed) = self.editor.document().get(id).cloned() else {
            return;
        };
        let p = &placed.primitive;
        let kind_id = words::kind_id(p.kind(), id);
        ui.horizontal_wrapped(|ui| {
            match self.editor.document().name(id) {
                Some(name) => {
                    ui.label(RichText::new(name).strong());
                    ui.label(RichText::new(format!("({kind_id})")).weak())
                }
                None => ui.label(RichText::new(kind_id.clone()).strong()),
            }
            .on_hover_text(words::kind_long(p.kind()));
            if ui
                .small_button("Rename…")
                .on_hover_text(format!(
                    "Name the part in the outliner ({})",
                    keys_text(ui.ctx(), Action::Rename)
                ))
                .clicked()
            {
                self.start_rename(id);
            }
        });
        self.pose_fields(ui, id, p);
        if placed.fit.strokes.is_empty() {
            ui.label("Placed freely: not snapped to any strokes")
                .on_hover_text("Drag it onto its strokes to snap it");
        } else {
            ui.label(format!(
                "Fits its {} strokes to {} on average",
                placed.fit.strokes.len(),
                words::length(placed.fit.rms, unit)
            ))
            .on_hover_text("The root mean square distance from the strokes to the part's outlines");
        }
        if let Some(verdict) = placed.fit.verdict {
            let confidence = placed.fit.confidence.map_or(String::new(), |c| {
                format!(" (confidence {:.0} %)", 100.0 * c)
            });
            ui.label(
                RichText::new(format!("snap {verdict}{confidence}"))
                    .color(super::canvas::verdict_color(verdict)),
            );
            if let Some(reason) = &placed.fit.reason {
                ui.label(RichText::new(format!("Why: {reason}.")).weak());
            }
        }
        if let Some((k, n)) = self.part_poses(id) {
            ui.horizontal(|ui| {
                ui.label(format!("Pose {k} of {n} the drawing allows"));
                let next = egui::Button::new("Next pose")
                    .shortcut_text(keys_text(ui.ctx(), Action::NextPose));
                if ui
                    .add_enabled(!self.busy(), next)
                    .on_hover_text(
                        "Place it in the next pose the snap found (another reading of its \
                         strokes); undo goes back",
                    )
                    .clicked()
                {
                    self.next_pose();
                }
            });
        }
        let fixed: Vec<(Quantity, f64)> = self
            .editor
            .document()
            .dimensions()
            .iter()
            .filter(|d| d.primitive == id)
            .map(|d| (d.quantity, d.value))
            .collect();
        let mut set = None;
        let mut free = None;
        egui::Grid::new("dimensions").num_columns(3).show(ui, |ui| {
            for quantity in Quantity::of_kind(p.kind()) {
                let Some(value) = p.quantity(*quantity) else {
                    continue;
                };
                let key = format!("{}:{}", id.0, quantity.name());
                let is_fixed = fixed.iter().find(|(q, _)| q == quantity).map(|(_, v)| *v);
                let name = ui.label(words::quantity_name(*quantity));
                let text = self
                    .panels
                    .typed
                    .entry(key.clone())
                    .or_insert_with(|| format!("{value:.2}"));
                let edit = ui.add(
                    egui::TextEdit::singleline(text)
                        .desired_width(90.0)
                        .min_size(egui::vec2(90.0, 0.0)),
                );
                let edit = edit.labelled_by(name.id).on_hover_text(format!(
                    "Type an exact {} in {} and press Enter: it becomes a hard constraint",
                    words::quantity_name(*quantity),
                    unit.symbol()
                ));
                let entered = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                if !edit.has_focus() && !entered {
                    *text = format!("{:.2}", is_fixed.unwrap_or(value));
                }
                if entered {
                    match text.trim().parse::<f64>() {
                        Ok(v) => set = Some((*quantity, v)),
                        Err(_) => self
                            .status
                            .push(format!("“{}” is not a number.", text.trim()), true),
                    }
                }
                ui.horizontal(|ui| {
                    ui.label(unit.symbol());
                    if is_fixed.is_some()
                        && ui
                            .button("free")
                            .on_hover_text(format!("Free the {}", words::quantity_name(*quantity)))
                            .clicked()
                    {
                        free = Some(*quantity);
                    }
                });
                ui.end_row();
            }
        });
        if let Some((quantity, value)) = set {
            match self.editor.dimension_set(id, quantity, value) {
                Ok(document) => self.resolve_in_background(
                    &format!(
                        "{}'s {} = {value} {}",
                        words::part_name(self.editor.document(), id),
                        words::quantity_name(quantity),
                        unit.symbol()
                    ),
                    document,
                    Some(vec![id]),
                ),
                Err(error) => self.warn(format!(
                    "{}: {error}",
                    words::part_name(self.editor.document(), id)
                )),
            }
        }
        if let Some(quantity) = free {
            self.editor.free_dimension(id, quantity);
        }
        ui.horizontal(|ui| {
            if ui
                .add_enabled(!self.busy(), egui::Button::new("Duplicate"))
                .clicked()
            {
                self.duplicate_selected();
            }
            if ui
                .add_enabled(!self.busy(), egui::Button::new("Delete"))
                .clicked()
            {
                self.delete_selected();
            }
        });
    }

    /// A number typed in a field of its own, shown as `value` while not edited; the
    /// typed number once Enter is pressed in it.
    fn number_field(
        &mut self,
        ui: &mut Ui,
        (key, name): (String, egui::Id),
        value: f64,
        hover: &str,
    ) -> Option<f64> {
        let text = self
            .panels
            .typed
            .entry(key)
            .or_insert_with(|| format!("{value:.2}"));
        let edit = ui
            .add(egui::TextEdit::singleline(text).desired_width(64.0))
            .labelled_by(name)
            .on_hover_text(hover);
        let entered = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if !edit.has_focus() && !entered {
            *text = format!("{value:.2}");
        }
        if !entered {
            return None;
        }
        let typed = text.trim().to_owned();
        match typed.parse::<f64>() {
            Ok(v) if v.is_finite() => Some(v),
            _ => {
                self.status
                    .push(format!("“{typed}” is not a number."), true);
                None
            }
        }
    }

    /// The part's centre and orientation, each typed in a field: Enter places the part
    /// exactly there ([`super::pose`]) and solves its relations (one undo step).
    fn pose_fields(&mut self, ui: &mut Ui, id: PrimitiveId, p: &Primitive) {
        let unit = self.unit();
        let centre = p.center();
        let mut moved = None;
        ui.horizontal_wrapped(|ui| {
            ui.label("Centre");
            let mut at = centre;
            for (k, axis) in ["X", "Y", "Z"].into_iter().enumerate() {
                let name = ui.label(axis).id;
                let hover = format!(
                    "The centre's {axis} in {}; Enter places the part there exactly \
                     (off its strokes) and solves its relations",
                    unit.symbol()
                );
                let key = (format!("{}:centre:{k}", id.0), name);
                if let Some(v) = self.number_field(ui, key, centre[k], &hover) {
                    at[k] = v;
                    moved = Some(super::pose::with_center(p, at));
                }
            }
            ui.label(unit.symbol());
        });
        let angles = super::pose::angles(p);
        if !angles.is_empty() {
            ui.horizontal_wrapped(|ui| {
                let mut degrees: Vec<f64> = angles.iter().map(|(_, a)| *a).collect();
                for (k, (name, value)) in angles.iter().enumerate() {
                    let label = ui.label(*name).id;
                    let hover = format!("The part's {name} in degrees; Enter turns it exactly so");
                    let key = (format!("{}:angle:{k}", id.0), label);
                    if let Some(v) = self.number_field(ui, key, *value, &hover) {
                        degrees[k] = v;
                        moved = super::pose::with_angles(p, &degrees);
                    }
                    ui.label("°");
                }
            });
        }
        if let Some(primitive) = moved {
            self.place_exactly(id, primitive);
        }
    }

    pub(crate) fn settings_window(&mut self, ctx: &egui::Context) {
        let mut open = self.panels.show_settings;
        egui::Window::new("Settings")
            .open(&mut open)
            .resizable(false)
            .show(ctx, |ui| {
                ui.heading("Document");
                let mut unit = self.unit();
                let busy = self.busy();
                ui.horizontal(|ui| {
                    let label = ui.label("Lengths are in").id;
                    ui.add_enabled_ui(!busy, |ui| {
                        egui::ComboBox::from_id_salt("document_unit")
                            .selected_text(unit.name())
                            .show_ui(ui, |ui| {
                                for u in words::Unit::ALL {
                                    ui.selectable_value(&mut unit, u, u.name());
                                }
                            })
                            .response
                            .labelled_by(label)
                            .on_disabled_hover_text(
                                "Wait for the running solve to change the unit",
                            );
                    });
                })
                .response
                .on_hover_text(super::files::UNIT_HOVER);
                self.set_unit(unit);
                ui.separator();
                ui.heading("Relation inference");
                let inference = &mut self.editor.settings_mut().inference;
                let mut enabled = inference.enabled_kinds().to_vec();
                egui::Grid::new("kinds").num_columns(3).show(ui, |ui| {
                    for (k, kind) in RelationKind::ALL.iter().enumerate() {
                        let mut on = enabled.contains(kind);
                        if ui
                            .checkbox(&mut on, kind.name().replace('_', " "))
                            .changed()
                        {
                            if on {
                                enabled.push(*kind);
                            } else {
                                enabled.retain(|x| x != kind);
                            }
                        }
                        if k % 3 == 2 {
                            ui.end_row();
                        }
                    }
                });
                let mut angle_degrees = inference.angle_degrees();
                let mut distance = inference.distance();
                let mut radius = inference.radius();
                let mut length = inference.length();
                ui.add(egui::Slider::new(&mut angle_degrees, 0.5..=30.0).text("angle (°)"));
                ui.add(egui::Slider::new(&mut distance, 0.01..=0.5).text("distance (× size)"));
                ui.add(egui::Slider::new(&mut radius, 0.005..=0.3).text("radius (relative)"));
                ui.add(egui::Slider::new(&mut length, 0.005..=0.3).text("length (relative)"));
                // The sliders stay within the valid ranges, so this keeps every change.
                if let Ok(changed) = crate::core::relation::InferenceSettings::new(
                    enabled,
                    angle_degrees,
                    distance,
                    radius,
                    length,
                ) {
                    *inference = changed;
                }
                if ui.button("Defaults").clicked() {
                    *inference = crate::core::relation::InferenceSettings::default();
                }
                ui.separator();
                ui.heading("Global solve");
                let global = &mut self.editor.settings_mut().global;
                let mut soft_weight = global.soft_weight();
                let soft = ui.add(
                    egui::Slider::new(&mut soft_weight, 0.01..=100.0)
                        .logarithmic(true)
                        .text("soft relation weight"),
                );
                if soft.changed() {
                    if let Ok(changed) = global.clone().with_soft_weight(soft_weight) {
                        *global = changed;
                    }
                }
                let mut max_worsening = global.max_worsening();
                let worsening = ui.add(
                    egui::Slider::new(&mut max_worsening, 1.2..=20.0)
                        .text("largest fit worsening (×)"),
                );
                if worsening.changed() {
                    if let Ok(changed) = global.clone().with_max_worsening(max_worsening) {
                        *global = changed;
                    }
                }
            });
        self.panels.show_settings = open;
    }
}

/// A relation being made by hand: its two parts, the feature of each (`None`: the
/// kind's usual one), its kind.
#[derive(Debug)]
struct Relate {
    parts: [Option<PrimitiveId>; 2],
    features: [Option<crate::core::primitive::Feature>; 2],
    kind: RelationKind,
}

impl Default for Relate {
    fn default() -> Self {
        Self {
            parts: [None; 2],
            features: [None; 2],
            kind: RelationKind::Coaxial,
        }
    }
}

/// The colour of suggested relations (in the panel and on the canvas).
const SUGGESTED: Color32 = Color32::from_rgb(80, 130, 210);

/// Why a relation is in the model, for its tooltip: its confidence and evidence when it
/// was inferred.
fn why_inferred(relation: &crate::core::model::Relation) -> String {
    match &relation.inferred {
        Some(inferred) => format!(
            "Inferred with confidence {:.0} %: {}",
            100.0 * inferred.confidence,
            inferred.evidence.describe(relation.kind)
        ),
        None => "Made by hand or read from a file (no evidence recorded)".to_owned(),
    }
}
