//! The editor grammars (issue 40): TextMate grammars of both forms in
//! docs/editors/, their names those of the program (the symbol
//! catalogue, the functions of tables B2–B5, the parameters, the
//! sections). Run with LMFILM_WRITE_GRAMMAR=1 to write them again after a
//! name changed.

use lmfilm::lsys::catalogue::MEANINGS;
use lmfilm::lsys::infix::{FUNCTIONS, PARAMETERS, SPECIALS};
use lmfilm::lsys::scan::{READABLE_SECTIONS, SECTIONS};
use serde_json::{json, Value};

fn words(names: &[&str]) -> String {
    format!("\\b({})\\b", names.join("|"))
}

fn readable() -> Value {
    let symbols: Vec<&str> = MEANINGS.iter().map(|m| m.name).collect();
    let mut functions: Vec<&str> = FUNCTIONS.iter().map(|f| f.0).collect();
    functions.extend(SPECIALS.iter().map(|s| s.0));
    let parameters: Vec<&str> = PARAMETERS.iter().map(|p| p.0).collect();
    json!({
        "name": "lmfilm (readable)",
        "scopeName": "source.lmr",
        "fileTypes": ["lmr"],
        "patterns": [
            {"name": "comment.block.lmr", "begin": "/\\*", "end": "\\*/"},
            {"name": "keyword.control.section.lmr", "match": format!("^\\s*{}", words(&READABLE_SECTIONS))},
            {"name": "keyword.control.lmr", "match": words(&["rule", "at_age", "left", "right", "if", "and", "or", "not"])},
            {"name": "variable.other.argument.lmr", "match": "\\b[a-z_][a-z0-9_]*(?=\\s*:)"},
            {"name": "entity.name.function.symbol.lmr", "match": words(&symbols)},
            {"name": "support.function.lmr", "match": words(&functions)},
            {"name": "variable.parameter.lmr", "match": words(&parameters)},
            {"name": "string.quoted.double.lmr", "begin": "\"", "end": "\""},
            {"name": "constant.character.symbol.lmr", "match": "'[^']'"},
            {"name": "constant.numeric.lmr", "match": "\\b[0-9]+(\\.[0-9]*)?([eE][+-]?[0-9]+)?\\b|\\.[0-9]+"},
            {"name": "keyword.operator.lmr", "match": "->|<=|>=|==|!=|[-+*/%^<>\\[\\]{}]"}
        ]
    })
}

fn classic() -> Value {
    json!({
        "name": "lmfilm (classic)",
        "scopeName": "source.lm",
        "fileTypes": ["lm"],
        "patterns": [
            {"name": "comment.block.lm", "begin": "/\\*", "end": "\\*/"},
            {"name": "keyword.control.section.lm", "match": words(&SECTIONS)},
            {"name": "keyword.control.lm", "match": "\\b(EndProductions|EndProb|End)\\b"},
            {"name": "meta.group.infix.lm", "begin": "\\(\\s*=", "end": "\\)(?=[^)]*$)|$"},
            {"name": "meta.group.lm", "match": "\\([^()\\n]*\\)"},
            {"name": "entity.name.function.symbol.lm", "match": "[A-Za-z0-9\\[\\]{}/^&$+\\-?.]"}
        ]
    })
}

#[test]
fn the_editor_grammars_name_what_the_program_names() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/editors");
    for (file, want) in [
        ("lmr.tmLanguage.json", readable()),
        ("lm.tmLanguage.json", classic()),
    ] {
        let path = format!("{dir}/{file}");
        if std::env::var_os("LMFILM_WRITE_GRAMMAR").is_some() {
            std::fs::write(&path, serde_json::to_string_pretty(&want).unwrap() + "\n").unwrap();
        }
        let shipped: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap())
            .unwrap_or_else(|e| panic!("{path}: {e}"));
        assert!(
            shipped == want,
            "{path} is out of date: run LMFILM_WRITE_GRAMMAR=1 cargo test --test lsys grammar"
        );
    }
}

#[test]
fn the_language_reference_lists_every_name() {
    let doc =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/language.md")).unwrap();
    for m in MEANINGS {
        let row = format!("| `{}` | `{}` |", m.name, m.classic().replace('|', "\\|"));
        assert!(doc.contains(&row), "docs/language.md §10.8 lacks `{row}`");
    }
}
