//! The symbol catalogue (issue 40, thesis 8.1.2: "self-explaining
//! identifiers for every symbol and every meaning of a parameter"): one
//! name per meaning of a symbol of appendix C, the selector values that
//! meaning fixes, and each of its parameters with its slot and unit. The
//! readable form spells symbols with these names, the converter picks
//! them, and the language server shows them on hover. docs/symbols.md is
//! the long form of each entry.

/// What a parameter's number means: checked where it is written as a
/// plain number, and said in errors and on hover.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unit {
    Degrees,
    /// Tenths of a degree (the thesis's view angle).
    TenthDegrees,
    Metres,
    /// A colour component in 0…1.
    Colour,
    /// A colour component in 0…255.
    Colour255,
    /// An actor's number: an integer ≥ 0.
    Actor,
    /// A material of table C.2.2: an integer 0…27 (or an imported one).
    Material,
    /// A table, object, surface, sound or source number: an integer ≥ 0.
    Index,
    /// An integer, any sign.
    Integer,
    /// 0 or 1.
    Flag,
    /// A joint of the built-in body: an integer 0…21.
    Joint,
    /// A motion number (`fig_bvh`), 0 for the rest pose, −1 seated.
    Motion,
    /// What a body is held by: 0 frame, 1 eyes, 2 right hand, 3 hips.
    Hold,
    /// Any number.
    Number,
    /// An automata command (table B6), as text.
    Text,
}

impl Unit {
    /// How the unit reads in a message: "an angle in degrees".
    pub fn describe(self) -> &'static str {
        match self {
            Unit::Degrees => "an angle in degrees",
            Unit::TenthDegrees => "an angle in tenths of a degree",
            Unit::Metres => "a length in metres",
            Unit::Colour => "a colour component in 0…1",
            Unit::Colour255 => "a colour component in 0…255",
            Unit::Actor => "an actor number (an integer ≥ 0)",
            Unit::Material => "a material number (an integer 0…27, or an imported material's)",
            Unit::Index => "a number (an integer ≥ 0)",
            Unit::Integer => "an integer",
            Unit::Flag => "a switch, 0 or 1",
            Unit::Joint => "a joint number, an integer 0…21",
            Unit::Motion => "a motion number (an integer; 0 the rest pose, −1 seated)",
            Unit::Hold => {
                "what holds the body: 0 its frame, 1 its eyes, 2 its right hand, 3 its hips"
            }
            Unit::Number => "a number",
            Unit::Text => "an automata command in quotes, e.g. \"goal 1 0 2\"",
        }
    }

    /// Why the plain number `v` is not of this unit, if it is not.
    pub fn reject(self, v: f64) -> Option<&'static str> {
        let integer = v.fract() == 0.0;
        let bad = match self {
            Unit::Colour => !(0.0..=1.0).contains(&v),
            Unit::Colour255 => !(0.0..=255.0).contains(&v),
            Unit::Actor | Unit::Index | Unit::Material => !integer || v < 0.0,
            Unit::Integer => !integer,
            Unit::Flag => v != 0.0 && v != 1.0,
            Unit::Joint => !integer || !(0.0..=21.0).contains(&v),
            Unit::Motion => !integer || v < -1.0,
            Unit::Hold => !integer || !(0.0..=3.0).contains(&v),
            Unit::Text => true,
            _ => false,
        };
        bad.then(|| self.describe())
    }
}

/// One parameter of a meaning: its name, its slot (0 the age, 1–3 x y z,
/// 4–6 f1 f2 f3) and its unit.
#[derive(Debug, Clone, Copy)]
pub struct Param {
    pub name: &'static str,
    pub slot: u8,
    pub unit: Unit,
}

/// One meaning of one symbol.
#[derive(Debug, Clone, Copy)]
pub struct Meaning {
    pub name: &'static str,
    pub ch: u8,
    /// Selector slots and the value this meaning fixes there (an empty
    /// group counts as 0).
    pub fixed: &'static [(u8, f64)],
    pub params: &'static [Param],
    /// A `]` whose par1 is a cut value (language.md §6.5).
    pub cut: bool,
    pub doc: &'static str,
}

/// The generic names of the seven slots, for symbols without a meaning
/// and for slots a meaning leaves free.
pub const SLOTS: [&str; 7] = ["age", "x", "y", "z", "f1", "f2", "f3"];

/// When each slot is evaluated, for hover and docs.
pub fn slot_timing(slot: u8) -> &'static str {
    match slot {
        0 => "the initial age, evaluated when the symbol is created",
        1..=3 => "fixed when the symbol is created",
        _ => "a growth function, evaluated each frame the word is drawn",
    }
}

const fn p(name: &'static str, slot: u8, unit: Unit) -> Param {
    Param { name, slot, unit }
}

const fn m(
    name: &'static str,
    ch: u8,
    fixed: &'static [(u8, f64)],
    params: &'static [Param],
    doc: &'static str,
) -> Meaning {
    Meaning {
        name,
        ch,
        fixed,
        params,
        cut: false,
        doc,
    }
}

use Unit::*;

const ANGLE: &[Param] = &[p("angle", 4, Degrees)];
const XYZ: &[Param] = &[p("x", 4, Metres), p("y", 5, Metres), p("z", 6, Metres)];
const DXYZ: &[Param] = &[p("dx", 4, Metres), p("dy", 5, Metres), p("dz", 6, Metres)];
const LENGTH: &[Param] = &[p("length", 4, Metres)];
const BOX: &[Param] = &[
    p("length", 4, Metres),
    p("width", 5, Metres),
    p("height", 6, Metres),
];
const CAPSULE: &[Param] = &[
    p("length", 4, Metres),
    p("radius_l", 5, Metres),
    p("radius_u", 6, Metres),
];
const TRUNK: &[Param] = &[
    p("length", 4, Metres),
    p("base_radius", 5, Metres),
    p("end_radius", 6, Metres),
];
const PYRAMID: &[Param] = &[
    p("height", 4, Metres),
    p("width_l", 5, Metres),
    p("width_u", 6, Metres),
];
const TABLE: &[Param] = &[p("table", 1, Integer)];
const RGB: &[Param] = &[
    p("red", 4, Colour),
    p("green", 5, Colour),
    p("blue", 6, Colour),
];
const FORCE: &[Param] = &[p("fx", 4, Number), p("fy", 5, Number), p("fz", 6, Number)];
const OBJECT: &[Param] = &[p("object", 4, Index)];
const ACTOR3: &[Param] = &[p("actor", 3, Actor)];
const BODY: &[Param] = &[
    p("motion", 4, Motion),
    p("height", 5, Metres),
    p("hold", 6, Hold),
];

/// Every named meaning. Where several meanings share a symbol, the
/// converter takes the first whose selectors a symbol's groups match.
pub const MEANINGS: &[Meaning] = &[
    // Turtle (C.1).
    m("turn_left", b'+', &[], ANGLE, "Turn left about U: R_U(angle)."),
    m("turn_right", b'-', &[], ANGLE, "Turn right about U: R_U(−angle)."),
    m("pitch_down", b'&', &[], ANGLE, "Pitch down about L: H toward −U."),
    m("pitch_up", b'^', &[], ANGLE, "Pitch up about L: H toward U."),
    m("roll_right", b'/', &[], ANGLE, "Roll right about H."),
    m("roll_left", b'$', &[(2, 0.0)], ANGLE, "Roll left about H: L toward U."),
    m("level_left", b'$', &[(2, 1.0)], &[], "Make L horizontal, H unchanged."),
    m("hang", b'$', &[(2, 2.0)], &[], "Make L horizontal, then point H down."),
    m("reset_orientation", b'$', &[(2, 3.0)], &[], "H, L, U back to +x, +y, +z; the position kept."),
    m("along_velocity", b'$', &[(2, 4.0)], &[], "H along the velocity of this symbol's particle."),
    m("follow_trace", b'$', &[(2, 5.0)], ACTOR3, "The turtle on the imported trajectory (import_trace) of an actor at the frame's time."),
    m("level_heading", b'$', &[(2, 6.0)], &[], "Make H horizontal, U up."),
    m("move", b'f', &[(3, 0.0)], &[p("distance", 4, Metres)], "Move forward along H without drawing."),
    m("move_by", b'f', &[(3, 1.0)], DXYZ, "Move by (dx, dy, dz) in the L-system's frame."),
    m("move_to", b'f', &[(3, 2.0)], XYZ, "Move to (x, y, z) in the L-system's frame."),
    m("move_local", b'f', &[(3, 3.0)], &[p("forward", 4, Metres), p("left", 5, Metres), p("up", 6, Metres)], "Move along H, L and U."),
    m("push", b'[', &[(1, 0.0)], &[], "Push the turtle, its material and its colour (a branch)."),
    m("store_state", b'[', &[(2, 1.0)], TABLE, "Store the turtle (position and axes) in the state table."),
    m("store_position", b'[', &[(2, 0.0)], TABLE, "Store the position in the position table."),
    m("pop", b']', &[(1, 0.0)], &[], "Pop what the last push saved (the branch ends)."),
    Meaning {
        cut: true,
        ..m("cut", b']', &[(2, 0.0)], &[p("kind", 1, Number)], "A cut at derivation (−100 < kind < 0 or 100): language.md §6.5.")
    },
    m("recall_state", b']', &[(2, 1.0)], TABLE, "Restore the turtle from the state table."),
    m("recall_position", b']', &[(2, 0.0)], TABLE, "Move to the position stored in the position table (a polygon vertex too)."),
    m("query", b'?', &[], &[], "Its x, y, z become the turtle position in the word."),
    m("vertex", b'.', &[], &[], "Add the turtle position as a vertex of the current polygon."),
    m("polygon", b'{', &[], &[], "Begin a polygon."),
    m("polygon_end", b'}', &[], &[p("flip", 1, Flag), p("copy", 2, Flag), p("sides", 3, Number), p("offset", 4, Metres)], "Draw the polygon; flip its normal, copy it at an offset, join the copies (sides 1) or edge them (sides 3)."),
    // Camera, material and light (C.2).
    m("eye", b'l', &[(3, 0.0)], XYZ, "The camera's eye at (x, y, z)."),
    m("look_at", b'l', &[(3, 1.0)], XYZ, "The camera's look-at point."),
    m("view", b'l', &[(3, 2.0)], &[p("angle", 4, TenthDegrees), p("aspect", 5, Number), p("twist", 6, Degrees)], "The vertical view angle, aspect ratio and twist."),
    m("light", b'l', &[(3, 3.0)], XYZ, "Light 3, white, at (x, y, z)."),
    m("eye_on_particle", b'l', &[(3, 4.0)], &[], "The eye at this symbol's particle."),
    m("look_along_particle", b'l', &[(3, 5.0)], &[p("ahead", 4, Metres)], "Look at the particle's position plus `ahead` along its velocity."),
    m("eye_with_microphone", b'l', &[(3, 8.0)], &[p("microphone", 2, Index), p("x", 4, Metres), p("y", 5, Metres), p("z", 6, Metres)], "The eye at (x, y, z), a microphone there."),
    m("eye_to_lookat", b'l', &[(3, 10.0)], &[p("microphone", 2, Index), p("x", 4, Metres), p("y", 5, Metres), p("z", 6, Metres)], "The eye at (x, y, z) looking at set_lookat's point, a microphone there."),
    m("sun", b'l', &[(3, 12.0)], DXYZ, "Light 3 becomes the sun, shining along (dx, dy, dz)."),
    m("sphere_light", b'l', &[(3, 13.0)], &[p("radius", 1, Metres), p("x", 4, Metres), p("y", 5, Metres), p("z", 6, Metres)], "Light 3 becomes a sphere light: soft shadows."),
    m("lens", b'l', &[(3, 14.0)], &[p("aperture", 4, Metres), p("focus", 5, Metres)], "The thin lens of the path tracer: aperture radius and distance in focus."),
    m("diffuse", b'm', &[(3, 1.0)], RGB, "The current material with this diffuse colour."),
    m("material", b'm', &[(3, 0.0)], &[p("n", 1, Material)], "The current material: table C.2.2 (1 green, 2 brown, 3 blue, 4 red, 7 white, 10 ball, …)."),
    m("segment_colour", b'r', &[], &[p("red", 4, Colour255), p("green", 5, Colour255), p("blue", 6, Colour255)], "The colour of the segments that follow."),
    // Shapes (C.3).
    m("segment", b'R', &[], LENGTH, "A segment (cylinder) along H; moves."),
    m("segment2", b'S', &[], LENGTH, "A segment, as `segment` (a second letter for productions)."),
    m("box", b'c', &[], BOX, "A box along H; moves."),
    m("box2", b'd', &[], BOX, "A box, as `box`."),
    m("capsule", b'O', &[], CAPSULE, "A capsule along H; moves."),
    m("capsule2", b'N', &[], CAPSULE, "A capsule, as `capsule`."),
    m("cylinder", b'o', &[], CAPSULE, "An elliptic cylinder closed by disks; moves."),
    m("trunk", b'P', &[], TRUNK, "A cone frustum with rounded ends; moves."),
    m("trunk2", b'Q', &[], TRUNK, "A trunk, as `trunk`."),
    m("sphere", b'a', &[], &[p("diameter", 4, Metres)], "A sphere centred at the turtle."),
    m("ellipsoid", b's', &[], &[p("diameter_h", 4, Metres), p("diameter_l", 5, Metres), p("diameter_u", 6, Metres)], "An ellipsoid centred at the turtle."),
    m("pyramid", b'p', &[], PYRAMID, "A pyramid, apex along H."),
    m("pyramid2", b'q', &[], PYRAMID, "A pyramid, as `pyramid`."),
    m("resolution", b'n', &[], &[p("n", 1, Index)], "The tessellation resolution of exports (3…1024)."),
    // Force fields and particles (C.4).
    m("tropism", b'v', &[(1, 0.0)], FORCE, "The tropism field (fx, fy, fz), evaluated at the turtle."),
    m("elasticity", b'v', &[(1, 1.0)], &[p("elasticity", 4, Number), p("mass", 5, Number)], "How much tropism bends (larger bends less) and the mass."),
    m("tropism_off", b'v', &[(1, 2.0)], &[], "No tropism for the symbols that follow."),
    m("automata", b'e', &[(1, 0.0)], &[p("command", 4, Text)], "An automata command (table B6) for the current actor."),
    m("force_field", b'e', &[(1, 10.0)], &[p("cutoff", 2, Metres), p("fx", 4, Number), p("fy", 5, Number), p("fz", 6, Number)], "The field the following particle carries (cutoff 0: unbounded)."),
    m("particle_term", b'e', &[(1, 11.0)], FORCE, "The following particle's individual force."),
    m("particle_start", b'C', &[(1, 0.0)], &[p("mass", 2, Number), p("vx", 4, Number), p("vy", 5, Number), p("vz", 6, Number)], "A particle starts at the turtle; the turtle then follows it."),
    m("particle_at", b'C', &[(1, 1.0)], XYZ, "The particle and the turtle at (x, y, z)."),
    m("racket_particle", b'C', &[(1, 5.0)], &[p("actor", 4, Actor)], "The particle at the eye of racket actor `actor`."),
    m("particle_here", b'C', &[(1, 6.0)], &[], "The particle at the turtle."),
    // Special symbols (C.6).
    m("object_end", b'D', &[(1, 1.0)], &[], "End the named object being recorded."),
    m("ground", b'D', &[(1, 2.0)], &[p("height", 4, Metres)], "A ground square ±1000 at y = height."),
    m("ground_zx", b'D', &[(1, 3.0)], &[p("height", 5, Metres)], "A ground square ±1000 at y = height."),
    m("object_scale", b'D', &[(1, 4.0)], &[p("sx", 4, Number), p("sy", 5, Number), p("sz", 6, Number)], "Scale the last placed object."),
    m("object_begin", b'D', &[(1, 6.0)], OBJECT, "Begin recording a named object."),
    m("object_place", b'D', &[(1, 7.0)], OBJECT, "Place a named object at the turtle."),
    m("object_translate", b'D', &[(1, 8.0)], DXYZ, "Translate the last placed object."),
    m("object_rotate", b'D', &[(1, 9.0)], &[p("ax", 4, Degrees), p("ay", 5, Degrees), p("az", 6, Degrees)], "Rotate the last placed object about x, y, z."),
    m("marble", b'D', &[(1, 10.0)], &[], "The current material becomes marble."),
    m("bump", b'D', &[(1, 11.0)], &[], "The current material becomes bumpy."),
    m("object_name", b'D', &[(1, 13.0)], OBJECT, "Begin recording a named object (as object_begin)."),
    m("sky", b'D', &[(1, 15.0)], &[p("red", 4, Number), p("green", 5, Number), p("blue", 6, Number)], "The sky sphere; with a colour, a uniform sky of that radiance."),
    m("clouds", b'D', &[(1, 16.0)], &[p("size_x", 4, Metres), p("size_y", 5, Metres), p("size_z", 6, Metres)], "A cloud layer 200 above the turtle."),
    m("eye_light", b'D', &[(1, 18.0)], &[], "A grey light at the current eye."),
    m("bounds_begin", b'D', &[(1, 20.0)], &[], "Begin measuring a bounding box."),
    m("bounds_end", b'D', &[(1, 21.0)], &[], "Print the bounding box of what was drawn since bounds_begin."),
    m("print_position", b'D', &[(1, 30.0)], &[], "Print the turtle position."),
    m("set_lookat", b'D', &[(1, 40.0)], &[], "The look-at point of eye_to_lookat."),
    m("tennis_court", b'D', &[(1, 41.0)], &[p("surround", 2, Flag)], "The tennis court at real size; surround 1 adds the grey surround."),
    m("body", b'D', &[(1, 50.0)], BODY, "A humanoid body: motion (0 rest, −1 seated), height in metres, held by 0 its frame, 1 eyes, 2 right hand, 3 hips."),
    m("to_joint", b'D', &[(1, 51.0)], &[p("joint", 4, Joint)], "The turtle to a joint of the last body."),
    m("body_undrawn", b'D', &[(1, 52.0)], BODY, "A body placed but not drawn (for figures drawn with to_joint)."),
    m("surface", b'B', &[], &[p("n", 1, Index), p("scale_h", 4, Number), p("scale_l", 5, Number), p("scale_u", 6, Number)], "An imported surface (fig_obj / fig_sm n) scaled along H, L, U."),
    m("play", b'T', &[(1, 0.0)], &[p("sound", 4, Index)], "Play a sound."),
    m("source_start", b'T', &[(1, 1.0)], &[p("sound", 4, Index), p("source", 5, Index)], "A sound source starts a sound at the turtle."),
    m("source_move", b'T', &[(1, 2.0)], &[p("source", 4, Index)], "A sound source moves to the turtle."),
    m("run_command", b'E', &[], &[p("script", 1, Index), p("run", 2, Flag), p("a", 4, Number), p("b", 5, Number), p("c", 6, Number)], "Run command_file script (only with --allow-commands)."),
    m("write_traces", b'I', &[], &[], "Write the trajectory records of the traced actors."),
    // Actors (C.5).
    m("actor", b'M', &[(1, 7.0)], ACTOR3, "The turtle at the actor's eye; it becomes the current actor."),
    m("memory_camera", b'M', &[(1, 14.0)], ACTOR3, "The camera of the actor's memory display at the turtle."),
    m("memory_look_at", b'M', &[(1, 15.0)], ACTOR3, "The look-at point of the actor's memory display."),
    m("place_eye", b'g', &[(1, 0.0)], &[], "The current actor's eye at the turtle, looking along H."),
    m("set_goal", b'g', &[(1, 1.0)], &[], "The current actor's local goal 0 at the turtle."),
    m("place_eye_level", b'g', &[(1, 2.0)], &[p("eye_height", 4, Metres)], "The eye at the turtle, at this height, looking level."),
];

/// The meaning called `name`.
pub fn named(name: &str) -> Option<&'static Meaning> {
    MEANINGS.iter().find(|m| m.name == name)
}

/// Every meaning's name, for suggestions and completion.
pub fn names() -> Vec<&'static str> {
    MEANINGS.iter().map(|m| m.name).collect()
}

/// Whether `kind` (par1 of a `]`) is a cut value (language.md §6.5).
pub fn is_cut(kind: f64) -> bool {
    kind == 100.0 || (kind > -100.0 && kind < 0.0)
}

impl Meaning {
    /// The parameter called `name`: the meaning's own, else a generic slot
    /// name the meaning leaves free.
    pub fn param(&self, name: &str) -> Option<Param> {
        if let Some(p) = self.params.iter().find(|p| p.name == name) {
            return Some(*p);
        }
        let slot = SLOTS.iter().position(|s| *s == name)? as u8;
        self.free(slot)
            .then_some(p(SLOTS[slot as usize], slot, Number))
    }

    /// Whether a slot is neither a selector nor one of the meaning's
    /// parameters, and its generic name is not taken by one.
    pub fn free(&self, slot: u8) -> bool {
        let name = SLOTS[slot as usize];
        !self.fixed.iter().any(|(s, _)| *s == slot)
            && !self.params.iter().any(|p| p.slot == slot || p.name == name)
    }

    /// The signature shown on hover and in errors:
    /// `sphere(diameter: a length in metres)`.
    pub fn signature(&self) -> String {
        let params: Vec<String> = self
            .params
            .iter()
            .map(|p| format!("{}: {}", p.name, p.unit.describe()))
            .collect();
        format!("{}({})", self.name, params.join(", "))
    }

    /// The classic spelling of its selectors: `f () () () (2)`.
    pub fn classic(&self) -> String {
        let last = self.fixed.iter().map(|(s, _)| *s).max();
        let mut out = (self.ch as char).to_string();
        if let Some(last) = last {
            for slot in 0..=last {
                match self.fixed.iter().find(|(s, _)| *s == slot) {
                    Some((_, v)) => out.push_str(&format!(" ({v})")),
                    None => out.push_str(" ()"),
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_identifiers_and_slots_distinct() {
        let mut seen = std::collections::BTreeSet::new();
        for m in MEANINGS {
            assert!(seen.insert(m.name), "{} twice", m.name);
            assert!(
                m.name.len() > 1,
                "{}: one letter names a raw symbol",
                m.name
            );
            assert!(m
                .name
                .bytes()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == b'_'));
            let mut slots: Vec<u8> = m.fixed.iter().map(|f| f.0).collect();
            slots.extend(m.params.iter().map(|p| p.slot));
            let n = slots.len();
            slots.sort();
            slots.dedup();
            assert_eq!(slots.len(), n, "{}: a slot twice", m.name);
        }
    }

    #[test]
    fn generic_names_reach_only_free_slots() {
        let move_to = named("move_to").unwrap();
        assert_eq!(move_to.param("x").unwrap().slot, 4);
        assert!(move_to.param("z").is_some_and(|p| p.slot == 6));
        assert!(move_to.param("age").is_some());
        assert!(move_to.param("f1").is_none(), "f1 is x's slot");
        let sphere = named("sphere").unwrap();
        assert_eq!(sphere.param("x").unwrap().slot, 1);
        assert_eq!(named("move_to").unwrap().classic(), "f () () () (2)");
        assert!(Unit::Colour.reject(1.5).is_some());
        assert!(Unit::Actor.reject(2.0).is_none());
        assert!(Unit::Actor.reject(0.5).is_some());
    }
}
