//! The `Options` section (table B1): every keyword is parsed and kept, even
//! where the feature it declares belongs to a later layer.

use super::parse::SECTIONS;
use super::scan::{suggestion, Scanner};
use crate::source::{Diagnostic, FileRef};

/// A keyword with its arguments, as in automata and sound protocol lists.
#[derive(Debug, Clone, PartialEq)]
pub struct Command {
    pub name: String,
    pub numbers: Vec<f64>,
    pub word: Option<String>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum OptionItem {
    MaxPart(i64),
    CommandFile {
        number: i64,
        script: FileRef,
        arg1: String,
        arg2: String,
    },
    FConst {
        index: i64,
        values: [f64; 8],
    },
    VlnetDeclare {
        exported: Vec<[i64; 3]>,
        imported: Vec<i64>,
        objects: Vec<i64>,
    },
    AudioPortHost {
        port: i64,
        host: String,
    },
    NbrActors(i64),
    VisionWinSize {
        actor: i64,
        edge: i64,
        max_colors: i64,
    },
    ActorAutomata {
        actor: i64,
        automata: i64,
        commands: Vec<Command>,
    },
    SoundEventFile {
        file: String,
        items: Vec<Command>,
    },
    /// `sound_file N FILE` (an extension): this scene's file for sound
    /// number N, in place of the library's (table D.1).
    SoundFile {
        number: i64,
        file: FileRef,
    },
    RsFilePathName {
        path: String,
        name: String,
    },
    /// Up to three frame intervals (first, last) for ray tracing.
    RsSwitch(Vec<i64>),
    Channels(Vec<String>),
    TraceActor {
        actor: i64,
        file: String,
    },
    ImportTrace {
        actor: i64,
        file: String,
    },
}

/// Largest `MaxPart`: ten million particles is far beyond what a frame
/// can evolve, yet keeps the particle table's size an honest number.
pub const MAX_PARTICLES: i64 = 10_000_000;

/// Longest list an option may announce (actors, objects, channels).
const MAX_LIST: i64 = 100_000;

/// (name, fewest numbers, most numbers, takes a word after the numbers).
type Spec = (&'static str, usize, usize, bool);

/// Automata commands of the BNF and table B6 (where they disagree on the
/// argument count, both counts are accepted).
const AUTOMATA: &[Spec] = &[
    ("KEYFRAMEdef", 1, 1, true),
    ("coll_test_func", 1, 1, false),
    ("heuristic", 1, 1, false),
    ("rel_search_level", 0, 1, false),
    ("goal", 3, 3, false),
    ("local_goal", 3, 4, false),
    ("rgb_interest", 4, 4, false),
    ("eps_arrived", 1, 2, false),
    ("eps_look_at_goal", 1, 2, false),
    ("eps_look_at", 1, 2, false),
    ("reset_goal", 0, 0, false),
    ("turtle", 1, 1, false),
    ("mem_displ_cubes", 0, 0, false),
    ("mem_no_displ", 0, 0, false),
    ("mem_displ_points", 0, 0, false),
    ("vis_mem_on", 0, 0, false),
    ("vis_mem_off", 0, 0, false),
    ("obs", 3, 3, false),
    ("lat", 3, 3, false),
    ("align", 3, 3, false),
    ("init", 4, 4, false),
    ("fov", 1, 1, false),
    ("interest", 2, 2, false),
    ("size_actor", 1, 1, false),
    ("dist_coll", 1, 1, false),
    ("tennis_state", 1, 1, false),
    ("state", 1, 1, false),
    ("optim_rate", 1, 1, false),
    ("speed", 1, 1, false),
    ("inertia", 1, 1, false),
    ("ahead", 1, 1, false),
    ("optim_ahead", 1, 1, false),
    ("vision_range", 3, 3, false),
    ("motor_init", 3, 3, false),
];

/// The sound protocol of table B7 (`PLAY n file` takes a word).
const SOUND: &[Spec] = &[
    ("INIT_source", 7, 7, false),
    ("INIT_mic", 7, 7, false),
    ("PLAY", 1, 1, true),
    ("SP", 4, 4, false),
    ("SO", 4, 4, false),
    ("MP", 4, 4, false),
    ("MO", 4, 4, false),
    ("TIME", 1, 1, false),
    ("Time", 1, 1, false),
    ("CONST_S", 7, 7, false),
    ("INIT_dist_matrix", 0, 0, false),
];

const KEYWORDS: &str = "MaxPart, command_file, fConst, VLNETdeclare, AUDIOport_host, NBR_actors, iVisionWinSize, actorNbr_automata, Sound_event_file, sound_file, rs_file_path_name, rs_switch, NbrChannels_listOfNames, trace_actor, import_trace";

fn commands(s: &mut Scanner, specs: &[Spec]) -> Result<Vec<Command>, Diagnostic> {
    let mut out = Vec::new();
    loop {
        let (_, w) = s.peek_word()?;
        let Some(&(name, min, max, word)) = specs.iter().find(|sp| sp.0 == w) else {
            return Ok(out);
        };
        let (at, _) = s.word(name)?;
        let numbers = s.numbers(max, &format!("an argument of `{name}`"))?;
        if numbers.len() < min {
            return Err(s.error(
                at,
                format!("`{name}` takes {min} numbers, found {}", numbers.len()),
            ));
        }
        let word = if word {
            Some(
                s.word(&format!("a file name after `{name}`"))?
                    .1
                    .to_string(),
            )
        } else {
            None
        };
        out.push(Command {
            name: name.to_string(),
            numbers,
            word,
        });
    }
}

/// Whether `name` is one plain path component that keeps every output
/// inside the output folder (DESIGN §5); the error says why not.
pub fn plain_name(name: &str) -> Result<(), &'static str> {
    if name.is_empty() || name == "." || name == ".." {
        return Err("is not a file name");
    }
    if name.contains(['/', '\\']) {
        return Err("has a folder separator");
    }
    if name.chars().any(char::is_control) {
        return Err("has a control character");
    }
    if name.len() > 200 {
        return Err("is longer than 200 bytes");
    }
    Ok(())
}

fn text(s: &mut Scanner, what: &str) -> Result<String, Diagnostic> {
    Ok(s.word(what)?.1.to_string())
}

fn file_ref(s: &mut Scanner, what: &str) -> Result<FileRef, Diagnostic> {
    let (at, w) = s.word(what)?;
    Ok(FileRef::new(s.src, at, w))
}

/// Parses one option; `None` when the next word is not an option keyword.
pub fn parse_option(s: &mut Scanner) -> Result<Option<OptionItem>, Diagnostic> {
    let (at, kw) = s.peek_word()?;
    if !KEYWORDS.split(", ").any(|k| k == kw) {
        return Ok(None);
    }
    s.word(kw)?;
    let item = match kw {
        "MaxPart" => {
            OptionItem::MaxPart(s.int_in("the maximal number of particles", 0..=MAX_PARTICLES)?)
        }
        "command_file" => OptionItem::CommandFile {
            number: s.int("the script number")?,
            script: file_ref(s, "the script name")?,
            arg1: text(s, "the first script argument")?,
            arg2: text(s, "the second script argument")?,
        },
        "fConst" => {
            let index = s.int("the fConst array number")?;
            if !(0..1000).contains(&index) {
                return Err(s.error(at, "fConst array number must be between 0 and 999"));
            }
            let v = s.numbers(8, "an fConst coefficient")?;
            if v.is_empty() {
                return Err(s.error(
                    at,
                    "`fConst` needs an array number and up to 8 coefficients",
                ));
            }
            let mut values = [0.0; 8];
            values[..v.len()].copy_from_slice(&v);
            OptionItem::FConst { index, values }
        }
        "VLNETdeclare" => {
            let mut exported = Vec::new();
            let mut imported = Vec::new();
            let mut objects = Vec::new();
            if s.at_keyword("Nbr_exported_actors")? {
                s.word("Nbr_exported_actors")?;
                for _ in 0..s.int_in("the number of exported actors", 0..=MAX_LIST)? {
                    exported.push([
                        s.int("a body key")?,
                        s.int("an object key")?,
                        s.int("an actor identifier")?,
                    ]);
                }
            }
            for (key, list) in [
                ("Nbr_imported_actors", &mut imported),
                ("Nbr_objects", &mut objects),
            ] {
                if s.at_keyword(key)? {
                    s.word(key)?;
                    for _ in 0..s.int_in("a count", 0..=MAX_LIST)? {
                        list.push(s.int("a number")?);
                    }
                }
            }
            OptionItem::VlnetDeclare {
                exported,
                imported,
                objects,
            }
        }
        "AUDIOport_host" => OptionItem::AudioPortHost {
            port: s.int("the port number")?,
            host: text(s, "the host name")?,
        },
        "NBR_actors" => OptionItem::NbrActors(s.int("the number of actors")?),
        "iVisionWinSize" => OptionItem::VisionWinSize {
            actor: s.int("the actor number")?,
            edge: s.int("the window edge length")?,
            max_colors: s.int("the maximal number of colours")?,
        },
        "actorNbr_automata" => {
            // The BNF repeats the actor number (`int Automata`, Automata =
            // `int int …`); both the two- and three-number forms are read.
            let mut ids = Vec::new();
            while ids.len() < 3 && s.at_number()? {
                ids.push(s.int("an actor or automata number")?);
            }
            if ids.len() < 2 {
                return Err(s.error(
                    at,
                    "`actorNbr_automata` needs the actor and automata numbers",
                ));
            }
            OptionItem::ActorAutomata {
                actor: ids[0],
                automata: ids[ids.len() - 1],
                commands: commands(s, AUTOMATA)?,
            }
        }
        "Sound_event_file" => OptionItem::SoundEventFile {
            file: text(s, "the sound event file name")?,
            items: commands(s, SOUND)?,
        },
        "rs_file_path_name" => {
            let path = text(s, "the file path")?;
            let (at, name) = s.word("the file name")?;
            if let Err(why) = plain_name(name) {
                return Err(s.error(
                    at,
                    format!("the film name `{name}` {why}: frames are written as FOLDER/frames/NAME.NNNN.png, so the name must be one plain file name such as `tree`"),
                ));
            }
            OptionItem::RsFilePathName {
                path,
                name: name.to_string(),
            }
        }
        "sound_file" => {
            let number = s.int("the sound number")?;
            if !(0..=i64::from(u32::MAX)).contains(&number) {
                return Err(s.error(at, "`sound_file` needs a sound number ≥ 0"));
            }
            OptionItem::SoundFile {
                number,
                file: file_ref(s, "the sound file name")?,
            }
        }
        "rs_switch" => {
            let v = s.numbers(6, "a frame number")?;
            if v.len() < 2 {
                return Err(s.error(at, "`rs_switch` needs frame intervals (first last …)"));
            }
            OptionItem::RsSwitch(v.iter().map(|x| *x as i64).collect())
        }
        "NbrChannels_listOfNames" => {
            let n = s.int_in("the number of channels", 0..=MAX_LIST)?;
            let mut names = Vec::new();
            for _ in 0..n {
                names.push(text(s, "a channel file name")?);
            }
            OptionItem::Channels(names)
        }
        "trace_actor" | "import_trace" => {
            let actor = s.int("the actor number")?;
            let file = text(s, "the trace file name")?;
            if kw == "trace_actor" {
                OptionItem::TraceActor { actor, file }
            } else {
                OptionItem::ImportTrace { actor, file }
            }
        }
        _ => unreachable!("every keyword of KEYWORDS has an arm"),
    };
    Ok(Some(item))
}

/// The error for a word that is neither an option nor a section.
pub fn unknown_option(s: &Scanner, at: usize, w: &str) -> Diagnostic {
    s.error(
        at,
        format!(
            "unknown option `{w}`; the Options section knows {KEYWORDS}{}",
            suggestion(w, &KEYWORDS.split(", ").chain(SECTIONS).collect::<Vec<_>>())
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::Source;

    #[test]
    fn every_option_keyword_is_parsed_and_kept() {
        let text = "MaxPart 100\n\
            command_file 0 cmd0.sh a b\n\
            fConst 5 1 2 3 4 5 6 7 8\n\
            VLNETdeclare Nbr_exported_actors 1 10 11 0 Nbr_imported_actors 2 1 2 Nbr_objects 1 7\n\
            AUDIOport_host 5000 localhost\n\
            NBR_actors 2\n\
            iVisionWinSize 0 64 20\n\
            actorNbr_automata 0 3 goal 1 2 3 local_goal 1 4 5 6 vis_mem_on speed 1.5 KEYFRAMEdef 2 walk.track\n\
            Sound_event_file film.events INIT_mic 0 0 0 0 0 0 1 INIT_source 1 1 2 3 0 0 1 PLAY 1 ball.aiff TIME 0.04 SP 1 4 5 6\n\
            rs_file_path_name /tmp frame\n\
            rs_switch 0 10 20 30 40 50\n\
            NbrChannels_listOfNames 2 a.chan b.chan\n\
            trace_actor 0 out.trace\n\
            import_trace 1 in.trace\n";
        let src = Source::new("o.lm", text);
        let mut s = Scanner::new(&src);
        let mut items = Vec::new();
        while let Some(o) = parse_option(&mut s).unwrap() {
            items.push(o);
        }
        assert!(s.at_end().unwrap());
        assert_eq!(items.len(), 14);
        assert_eq!(
            items[2],
            OptionItem::FConst {
                index: 5,
                values: [1., 2., 3., 4., 5., 6., 7., 8.]
            }
        );
        let OptionItem::ActorAutomata {
            actor,
            automata,
            commands,
        } = &items[7]
        else {
            panic!()
        };
        assert_eq!((*actor, *automata, commands.len()), (0, 3, 5));
        assert_eq!(commands[1].numbers, [1., 4., 5., 6.]);
        assert_eq!(commands[4].word.as_deref(), Some("walk.track"));
        let OptionItem::SoundEventFile { items: sound, .. } = &items[8] else {
            panic!()
        };
        assert_eq!(
            sound.iter().map(|c| c.name.as_str()).collect::<Vec<_>>(),
            ["INIT_mic", "INIT_source", "PLAY", "TIME", "SP"]
        );
        assert_eq!(
            items[13],
            OptionItem::ImportTrace {
                actor: 1,
                file: "in.trace".into()
            }
        );
    }
}
