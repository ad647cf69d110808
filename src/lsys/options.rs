//! The `Options` section (table B1): every keyword is parsed and kept, even
//! where the feature it declares belongs to a later layer.

use super::automata::{parse_actor_automata, ActorAutomata, Located, Span};
use super::scan::SECTIONS;
use super::scan::{suggestion, Scanner};
use crate::source::{Diagnostic, FileRef};

/// A keyword with its arguments, as in the sound protocol list (automata
/// commands are typed: [`super::automata::AutomataCommand`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Command {
    pub name: String,
    pub numbers: Vec<f64>,
    pub word: Option<String>,
    /// Where its keyword is in the definition's text, for errors.
    pub at: usize,
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
    NbrActors(Located<i64>),
    VisionWinSize {
        actor: Located<i64>,
        edge: Located<i64>,
        max_colors: Located<i64>,
    },
    ActorAutomata(ActorAutomata),
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
    /// `NbrChannels_listOfNames n file…`: the data channel files `?50`
    /// reads, channel k being the k-th name (0-based).
    Channels(Vec<FileRef>),
    /// `trace_actor actor file`: where `I` writes the actor's records.
    TraceActor {
        actor: i64,
        file: FileRef,
    },
    /// `import_trace actor file`: the trajectory `$` par2 = 5 follows.
    ImportTrace {
        actor: i64,
        file: FileRef,
    },
}

/// Largest `MaxPart`: ten million particles is far beyond what a frame
/// can evolve, yet keeps the particle table's size an honest number.
pub const MAX_PARTICLES: i64 = 10_000_000;

/// Most data channels a film declares (thesis 6.3.3).
pub const MAX_CHANNELS: i64 = 10;

/// Longest list an option may announce (actors, objects, channels).
const MAX_LIST: i64 = 100_000;

/// (name, fewest numbers, most numbers, takes a word after the numbers).
type Spec = (&'static str, usize, usize, bool);

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
    ("INIT_ears", 2, 2, false),
    ("INIT_ambix", 1, 1, false),
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
                format!(
                    "`{name}` takes {min} number{}, found {}",
                    if min == 1 { "" } else { "s" },
                    numbers.len()
                ),
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
            at,
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

/// An integer with the location of its word.
fn located_int(s: &mut Scanner, what: &str) -> Result<Located<i64>, Diagnostic> {
    let at = s.peek_word()?.0;
    Ok(Located {
        value: s.int(what)?,
        span: Span::new(s.src, at),
    })
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
        "NBR_actors" => OptionItem::NbrActors(located_int(s, "the number of actors")?),
        "iVisionWinSize" => OptionItem::VisionWinSize {
            actor: located_int(s, "the actor number")?,
            edge: located_int(s, "the window edge length")?,
            max_colors: located_int(s, "the maximal number of colours")?,
        },
        "actorNbr_automata" => OptionItem::ActorAutomata(parse_actor_automata(s, at)?),
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
            // Up to 10 data channels (thesis 6.3.3).
            let n = s.int_in("the number of channels", 0..=MAX_CHANNELS)?;
            let mut names = Vec::new();
            for _ in 0..n {
                names.push(file_ref(s, "a channel file name")?);
            }
            OptionItem::Channels(names)
        }
        "trace_actor" | "import_trace" => {
            let actor = s.int("the actor number")?;
            let file = file_ref(s, "the trace file name")?;
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

/// The scene's `rs_switch` values, if it has one (the last one wins, as a
/// later line of the Options section overrides an earlier one).
pub fn rs_switch(options: &[OptionItem]) -> Option<&[i64]> {
    options.iter().rev().find_map(|o| match o {
        OptionItem::RsSwitch(values) => Some(values.as_slice()),
        _ => None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lsys::automata::{Automata, AutomataCommand};
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
        let OptionItem::ActorAutomata(ActorAutomata {
            actor,
            automata,
            commands,
        }) = &items[7]
        else {
            panic!()
        };
        assert_eq!(
            (actor.value, automata.value, commands.len()),
            (0, Automata::WalkLocal, 5)
        );
        assert_eq!(
            commands[1].command,
            AutomataCommand::LocalGoal {
                index: Some(1),
                at: [4., 5., 6.]
            }
        );
        assert_eq!(
            (commands[1].span.line(), commands[1].span.column()),
            (8, 34)
        );
        let AutomataCommand::KeyframeDef { n: 2, file } = &commands[4].command else {
            panic!("{:?}", commands[4])
        };
        assert_eq!(file.name, "walk.track");
        let OptionItem::SoundEventFile { items: sound, .. } = &items[8] else {
            panic!()
        };
        assert_eq!(
            sound.iter().map(|c| c.name.as_str()).collect::<Vec<_>>(),
            ["INIT_mic", "INIT_source", "PLAY", "TIME", "SP"]
        );
        let OptionItem::ImportTrace { actor: 1, file } = &items[13] else {
            panic!("{:?}", items[13])
        };
        assert_eq!((file.name.as_str(), file.at.line), ("in.trace", 14));
    }
}
