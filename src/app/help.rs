//! Help for the user: the one table of keyboard shortcuts ([`SHORTCUTS`]) that both the
//! shortcut handler and Help → Keyboard shortcuts (F1) read, so the two cannot drift;
//! the table of mouse controls ([`MOUSE`]) that the same window and the legend shown
//! during a palette drag read; and the hint shown once on the built-in sample.

use egui::{Key, KeyboardShortcut, Modifiers, RichText, Ui};

use super::GeosnapApp;

/// What a shortcut does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Action {
    Redo,
    Undo,
    SaveAs,
    Save,
    Open,
    New,
    Export,
    Duplicate,
    Delete,
    Rename,
    Cancel,
    Fit,
    SelectTool,
    DrawTool,
    EraseTool,
    ReclassifyTool,
    FrontView,
    TopView,
    SideView,
    IsometricView,
    HomeView,
    NextPose,
    Help,
}

/// A keyboard shortcut: its keys (any of them), and what it does in words.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shortcut {
    pub action: Action,
    /// The keys, the first one shown first.
    pub keys: &'static [KeyboardShortcut],
    /// What it does, as the help window lists it.
    pub what: &'static str,
}

const fn key(modifiers: Modifiers, key: Key) -> KeyboardShortcut {
    KeyboardShortcut::new(modifiers, key)
}

const COMMAND: Modifiers = Modifiers::COMMAND;
const COMMAND_SHIFT: Modifiers = Modifiers {
    shift: true,
    ..Modifiers::COMMAND
};
const NONE: Modifiers = Modifiers::NONE;

/// Every keyboard shortcut of the app. The handler tries them in this order (a
/// shortcut with more modifiers before the same key with fewer: Ctrl+Shift+Z before
/// Ctrl+Z). Plain keys (no Ctrl / Cmd) do nothing while a text field has the keyboard.
pub(crate) const SHORTCUTS: &[Shortcut] = &[
    Shortcut {
        action: Action::Redo,
        keys: &[key(COMMAND_SHIFT, Key::Z), key(COMMAND, Key::Y)],
        what: "Redo",
    },
    Shortcut {
        action: Action::Undo,
        keys: &[key(COMMAND, Key::Z)],
        what: "Undo",
    },
    Shortcut {
        action: Action::SaveAs,
        keys: &[key(COMMAND_SHIFT, Key::S)],
        what: "Save as…",
    },
    Shortcut {
        action: Action::Save,
        keys: &[key(COMMAND, Key::S)],
        what: "Save",
    },
    Shortcut {
        action: Action::Open,
        keys: &[key(COMMAND, Key::O)],
        what: "Open…",
    },
    Shortcut {
        action: Action::New,
        keys: &[key(COMMAND, Key::N)],
        what: "New drawing",
    },
    Shortcut {
        action: Action::Export,
        keys: &[key(COMMAND, Key::E)],
        what: "Export glTF…",
    },
    Shortcut {
        action: Action::Duplicate,
        keys: &[key(COMMAND, Key::D)],
        what: "Duplicate the selected part",
    },
    Shortcut {
        action: Action::Delete,
        keys: &[key(NONE, Key::Delete), key(NONE, Key::Backspace)],
        what: "Delete the selected part",
    },
    Shortcut {
        action: Action::Rename,
        keys: &[key(NONE, Key::F2)],
        what: "Rename the selected part (in the outliner: Enter keeps the name, Esc does not)",
    },
    Shortcut {
        action: Action::Cancel,
        keys: &[key(NONE, Key::Escape)],
        what: "Cancel the drag, the solve or the stroke; else deselect",
    },
    Shortcut {
        action: Action::Fit,
        keys: &[key(NONE, Key::F)],
        what: "Fit the drawing and the model in their views",
    },
    Shortcut {
        action: Action::SelectTool,
        keys: &[key(NONE, Key::V)],
        what: "Select tool",
    },
    Shortcut {
        action: Action::DrawTool,
        keys: &[key(NONE, Key::B)],
        what: "Draw tool",
    },
    Shortcut {
        action: Action::EraseTool,
        keys: &[key(NONE, Key::E)],
        what: "Erase tool",
    },
    Shortcut {
        action: Action::ReclassifyTool,
        keys: &[key(NONE, Key::C)],
        what: "Reclassify tool",
    },
    Shortcut {
        action: Action::FrontView,
        keys: &[key(NONE, Key::Num1)],
        what: "3D view from the front, in perspective",
    },
    Shortcut {
        action: Action::TopView,
        keys: &[key(NONE, Key::Num2)],
        what: "3D view from the top",
    },
    Shortcut {
        action: Action::SideView,
        keys: &[key(NONE, Key::Num3)],
        what: "3D view from the side (the right)",
    },
    Shortcut {
        action: Action::IsometricView,
        keys: &[key(NONE, Key::Num4)],
        what: "Isometric 3D view",
    },
    Shortcut {
        action: Action::HomeView,
        keys: &[key(NONE, Key::Num0), key(NONE, Key::Home)],
        what: "3D view from the drawing (home): its camera, the strokes and image behind the \
               model, fitted (also with an empty model)",
    },
    Shortcut {
        action: Action::NextPose,
        keys: &[key(NONE, Key::Tab)],
        what: "Next pose the snap found: while dragging, or for the selected part",
    },
    Shortcut {
        action: Action::Help,
        keys: &[key(NONE, Key::F1)],
        what: "Keyboard shortcuts and mouse controls (this window)",
    },
];

/// Where a mouse control applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Place {
    /// While a primitive is dragged from the palette (or a part is moved).
    Drag,
    /// On the drawing.
    Canvas,
    /// In the 3D view.
    View3d,
    /// In the outliner (the list of parts).
    Outliner,
}

impl Place {
    fn heading(self) -> &'static str {
        match self {
            Self::Drag => "While dragging a primitive",
            Self::Canvas => "On the drawing",
            Self::View3d => "In the 3D view",
            Self::Outliner => "In the list of parts",
        }
    }
}

/// A mouse control: where, the gesture, and what it does.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MouseControl {
    pub place: Place,
    pub gesture: &'static str,
    pub what: &'static str,
}

const fn mouse(place: Place, gesture: &'static str, what: &'static str) -> MouseControl {
    MouseControl {
        place,
        gesture,
        what,
    }
}

/// Every mouse control of the app, as the canvas, the drag and the 3D view handle them.
pub(crate) const MOUSE: &[MouseControl] = &[
    mouse(
        Place::Drag,
        "Move",
        "The part snaps to the strokes under it (orange preview)",
    ),
    mouse(Place::Drag, "Wheel", "Size"),
    mouse(Place::Drag, "Shift + wheel", "Turn the axis"),
    mouse(
        Place::Drag,
        "Release",
        "Place it: snapped, or as dragged where the strokes do not support it (off the \
         drawing: nothing)",
    ),
    mouse(
        Place::Drag,
        "Alt + release",
        "Place it as dragged, without snapping",
    ),
    mouse(
        Place::Canvas,
        "Drag from the palette",
        "Place a primitive on the drawing",
    ),
    mouse(
        Place::Canvas,
        "Click (Select tool)",
        "Select the part under the cursor",
    ),
    mouse(
        Place::Canvas,
        "Drag a part (Select tool)",
        "Move it and snap it again",
    ),
    mouse(Place::Canvas, "Drag (Draw tool)", "Draw a stroke"),
    mouse(
        Place::Canvas,
        "Click or drag (Erase tool)",
        "Erase the strokes under the cursor",
    ),
    mouse(
        Place::Canvas,
        "Click (Reclassify tool)",
        "Switch a stroke between end (blue) and outline (black)",
    ),
    mouse(Place::Canvas, "Right or middle drag, Space + drag", "Pan"),
    mouse(Place::Canvas, "Wheel", "Zoom about the cursor"),
    mouse(
        Place::Canvas,
        "Drop a file on the window",
        "Open it (drawing, SVG, image or session)",
    ),
    mouse(
        Place::View3d,
        "Drag",
        "Orbit (stays above the grid; leaves the view from the drawing)",
    ),
    mouse(Place::View3d, "Right or middle drag, Shift + drag", "Pan"),
    mouse(Place::View3d, "Wheel", "Zoom"),
    mouse(Place::View3d, "Double-click", "Fit the model"),
    mouse(Place::Outliner, "Click", "Select the part"),
    mouse(
        Place::Outliner,
        "Double-click, or right-click and Rename…",
        "Name the part (Enter keeps the name, Esc does not)",
    ),
];

/// What every keyboard shortcut does, in the order Help → Keyboard shortcuts lists
/// them (the same table the shortcut handler reads).
pub fn shortcut_descriptions() -> Vec<&'static str> {
    SHORTCUTS.iter().map(|s| s.what).collect()
}

/// The shortcut of `action`, as a menu shows it ("Ctrl+Z"), or "" when it has none.
pub(crate) fn keys_text(ctx: &egui::Context, action: Action) -> String {
    SHORTCUTS
        .iter()
        .find(|s| s.action == action)
        .and_then(|s| s.keys.first())
        .map(|k| format_keys(ctx, *k))
        .unwrap_or_default()
}

/// A shortcut as the user reads it: egui's platform names, with Esc for Escape.
fn format_keys(ctx: &egui::Context, shortcut: KeyboardShortcut) -> String {
    ctx.format_shortcut(&shortcut).replace("Escape", "Esc")
}

/// Whether `shortcut` was pressed this frame (it is then consumed). Shortcuts with
/// Ctrl / Cmd work everywhere; plain keys only when no text field has the keyboard,
/// and only with no modifier held.
fn pressed(ctx: &egui::Context, shortcut: KeyboardShortcut, typing: bool) -> bool {
    if shortcut.modifiers.command || shortcut.modifiers.ctrl {
        ctx.input_mut(|i| i.consume_shortcut(&shortcut))
    } else {
        !typing && ctx.input(|i| i.key_pressed(shortcut.logical_key) && i.modifiers.is_none())
    }
}

/// The keys of [`SHORTCUTS`], under a heading.
fn keys_table(ui: &mut Ui) {
    ui.heading("Keys");
    egui::Grid::new("shortcut_keys")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            for shortcut in SHORTCUTS {
                let keys: Vec<String> = shortcut
                    .keys
                    .iter()
                    .map(|k| format_keys(ui.ctx(), *k))
                    .collect();
                ui.label(RichText::new(keys.join(" or ")).strong());
                ui.label(shortcut.what);
                ui.end_row();
            }
        });
}

/// The mouse controls of [`MOUSE`], by place, under headings.
fn mouse_table(ui: &mut Ui) {
    for place in [Place::Drag, Place::Canvas, Place::View3d, Place::Outliner] {
        ui.heading(place.heading());
        egui::Grid::new(("mouse", place as u8))
            .num_columns(2)
            .striped(true)
            .show(ui, |ui| {
                for control in MOUSE.iter().filter(|c| c.place == place) {
                    ui.label(RichText::new(control.gesture).strong());
                    ui.label(control.what);
                    ui.end_row();
                }
                if place == Place::Drag {
                    let tab = keys_text(ui.ctx(), Action::NextPose);
                    ui.label(RichText::new(tab).strong());
                    ui.label("Show the next pose the snap found");
                    ui.end_row();
                    let esc = keys_text(ui.ctx(), Action::Cancel);
                    ui.label(RichText::new(esc).strong());
                    ui.label("Cancel the drag");
                    ui.end_row();
                }
            });
        ui.add_space(8.0);
    }
}

/// The state of the help: whether the shortcuts window is open, and whether the first-run
/// hint is still to be shown.
#[derive(Debug, Default)]
pub(crate) struct Help {
    pub shortcuts_open: bool,
    /// Shown on the built-in sample until dismissed (once per settings profile).
    pub first_run_hint: bool,
    /// Whether the hint was dismissed (persisted).
    pub hint_seen: bool,
}

/// The storage key of [`Help::hint_seen`].
pub(crate) const HINT_SEEN_KEY: &str = "first_run_hint_seen";

impl GeosnapApp {
    /// Runs the shortcuts pressed this frame, from [`SHORTCUTS`].
    pub(crate) fn shortcuts(&mut self, ctx: &egui::Context) {
        // A name being typed keeps the plain keys, Esc included, even on the frame
        // where egui has already taken the keyboard back from its field.
        let typing = ctx.egui_wants_keyboard_input() || self.panels.renaming().is_some();
        for shortcut in SHORTCUTS {
            if shortcut.keys.iter().any(|k| pressed(ctx, *k, typing)) {
                self.run_action(ctx, shortcut.action);
            }
        }
    }

    /// Does what `action` names (a shortcut or its menu entry).
    pub(crate) fn run_action(&mut self, ctx: &egui::Context, action: Action) {
        use super::files::After;
        use super::view3d::Standard;
        use super::Tool;
        match action {
            Action::Redo => self.redo(),
            Action::Undo => self.undo(),
            Action::SaveAs => {
                self.save_as(ctx);
            }
            Action::Save => {
                self.save(ctx);
            }
            Action::Open => self.request(ctx, After::Open(None)),
            Action::New => self.request(ctx, After::New),
            Action::Export => self.export_dialog(),
            Action::Duplicate => self.duplicate_selected(),
            Action::Delete => self.delete_selected(),
            Action::Rename => {
                if let Some(id) = self.selection {
                    self.start_rename(id);
                }
            }
            Action::Cancel => self.escape(),
            Action::Fit => {
                self.canvas.request_fit();
                self.view3d.request_fit();
            }
            Action::SelectTool => *self.canvas.tool_mut() = Tool::Select,
            Action::DrawTool => *self.canvas.tool_mut() = Tool::Draw,
            Action::EraseTool => *self.canvas.tool_mut() = Tool::Erase,
            Action::ReclassifyTool => *self.canvas.tool_mut() = Tool::Reclassify,
            Action::FrontView => self.view3d.standard(Standard::Front),
            Action::TopView => self.view3d.standard(Standard::Top),
            Action::SideView => self.view3d.standard(Standard::Side),
            Action::IsometricView => self.view3d.standard(Standard::Isometric),
            Action::HomeView => self.view3d.drawing_view(),
            Action::NextPose => {
                self.next_pose();
                // Tab is the pose key here, not a move of the keyboard focus.
                ctx.memory_mut(|m| m.move_focus(egui::FocusDirection::None));
            }
            Action::Help => self.help.shortcuts_open = !self.help.shortcuts_open,
        }
    }

    /// Esc: cancels the drag, else the running solve, else the file being opened, else
    /// the stroke being drawn, else the selection.
    fn escape(&mut self) {
        if self.drag.is_some() {
            self.cancel_drag();
            self.say("Drag cancelled.");
        } else if self.busy() {
            self.cancel_job();
        } else if !self.cancel_loading() && !self.canvas.cancel_stroke() {
            self.selection = None;
        }
    }

    /// Whether the Help → Keyboard shortcuts window is open.
    pub fn shortcuts_window_open(&self) -> bool {
        self.help.shortcuts_open
    }

    /// The Help → Keyboard shortcuts window: every row of [`SHORTCUTS`] and [`MOUSE`].
    pub(crate) fn shortcuts_window(&mut self, ctx: &egui::Context) {
        let mut open = self.help.shortcuts_open;
        egui::Window::new("Keyboard shortcuts")
            .open(&mut open)
            .collapsible(false)
            .resizable(false)
            .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
            .show(ctx, |ui| {
                ui.horizontal_top(|ui| {
                    ui.vertical(keys_table);
                    ui.add_space(24.0);
                    ui.vertical(mouse_table);
                });
            });
        self.help.shortcuts_open = open;
    }

    /// The legend of the drag controls (gesture, what it does) while a primitive is
    /// dragged, empty otherwise: the mouse controls of a drag and the
    /// key that cancels.
    pub fn drag_legend(&self, ctx: &egui::Context) -> Vec<(String, String)> {
        if self.drag.is_none() {
            return Vec::new();
        }
        let mut rows: Vec<(String, String)> = MOUSE
            .iter()
            .filter(|c| c.place == Place::Drag && c.gesture != "Move")
            .map(|c| (c.gesture.to_owned(), c.what.to_owned()))
            .collect();
        let tab = keys_text(ctx, Action::NextPose);
        let pose = match self.drag.as_ref().map(super::Drag::pose) {
            Some((k, n)) if n > 1 => format!("Next pose the snap found ({k} of {n})"),
            Some((_, 1)) => "Next pose (this drop has one)".to_owned(),
            _ => "Next pose the snap found".to_owned(),
        };
        rows.push((tab, pose));
        rows.push((keys_text(ctx, Action::Cancel), "Cancel".to_owned()));
        rows
    }

    /// The legend of the drag controls, in the canvas's lower left corner while a
    /// primitive is dragged ([`Self::drag_legend`]).
    pub(crate) fn paint_drag_legend(&self, painter: &egui::Painter, rect: egui::Rect) {
        let rows = self.drag_legend(painter.ctx());
        if rows.is_empty() {
            return;
        }
        let font = egui::FontId::proportional(13.0);
        let line = 18.0;
        let width = |text: &str| {
            painter
                .layout_no_wrap(text.to_owned(), font.clone(), egui::Color32::BLACK)
                .size()
                .x
        };
        let column = rows.iter().map(|(g, _)| width(g)).fold(0.0, f32::max) + 20.0;
        let widest = rows.iter().map(|(_, w)| width(w)).fold(0.0, f32::max);
        let size = egui::vec2(column + widest + 20.0, line * rows.len() as f32 + 12.0);
        let frame =
            egui::Rect::from_min_size(rect.left_bottom() + egui::vec2(10.0, -size.y - 10.0), size);
        painter.rect(
            frame,
            6.0,
            egui::Color32::from_white_alpha(235),
            egui::Stroke::new(1.0, egui::Color32::from_gray(190)),
            egui::StrokeKind::Inside,
        );
        for (k, (gesture, what)) in rows.iter().enumerate() {
            let y = frame.top() + 6.0 + line * k as f32;
            painter.text(
                egui::pos2(frame.left() + 10.0, y),
                egui::Align2::LEFT_TOP,
                gesture,
                egui::FontId::proportional(13.0),
                egui::Color32::from_gray(30),
            );
            painter.text(
                egui::pos2(frame.left() + 10.0 + column, y),
                egui::Align2::LEFT_TOP,
                what,
                font.clone(),
                egui::Color32::from_gray(70),
            );
        }
    }

    /// The first-run hint on the built-in sample, in the canvas's upper right corner,
    /// until "Got it" (remembered in the settings when the app has them).
    pub(crate) fn first_run_hint(&mut self, ui: &Ui, rect: egui::Rect) {
        // One thing at a time: not over a question (the recovery prompt), the shortcuts
        // window or a file being opened.
        if !self.help.first_run_hint
            || self.help.shortcuts_open
            || self.asking()
            || self.loading.is_some()
        {
            return;
        }
        let help_keys = keys_text(ui.ctx(), Action::Help);
        egui::Area::new(egui::Id::unique("first_run_hint"))
            .order(egui::Order::Middle)
            .fixed_pos(rect.right_top() + egui::vec2(-330.0, 36.0))
            .show(ui.ctx(), |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    ui.set_max_width(300.0);
                    ui.label(RichText::new("Welcome to geosnap").strong());
                    ui.label(
                        "This is a sample drawing of a vase. Drag “Profile” from the palette \
                         onto it: the part snaps to the strokes while you drag, and is \
                         placed when you release.",
                    );
                    ui.label(
                        "While dragging: wheel to size, Shift + wheel to turn, Tab for another \
                         pose, Alt + release to place without snapping, Esc to cancel.",
                    );
                    ui.label(format!("{help_keys} lists every shortcut (Help menu)."));
                    if ui.button("Got it").clicked() {
                        self.help.first_run_hint = false;
                        self.help.hint_seen = true;
                    }
                });
            });
    }
}
