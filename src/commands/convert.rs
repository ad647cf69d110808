//! `lmfilm convert`: a definition file spelt in the other form (issue
//! 40): classic `.lm` to readable `.lmr`, or back. Both spellings parse
//! into the same definition.

use std::path::Path;

use crate::error::{Error, Result};
use crate::lsys::animation::read_source;
use crate::lsys::readable::is_readable;
use crate::lsys::readable_writer::to_readable;
use crate::lsys::thesis_form::to_thesis;

/// The other spelling of `input`: written to `output`, or printed.
pub fn convert(input: &Path, output: Option<&Path>) -> Result<()> {
    let src = read_source(input).map_err(|e| Error::input(e.to_string()))?;
    let text = if is_readable(&src.name) {
        to_thesis(&src)?
    } else {
        to_readable(&src)?
    };
    match output {
        None => print!("{text}"),
        Some(out) => {
            let same = |a: &Path, b: &Path| {
                a == b || matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
            };
            if same(out, input) {
                return Err(Error::input(format!(
                    "{}: the output would overwrite the input",
                    out.display()
                )));
            }
            std::fs::write(out, &text)
                .map_err(|e| Error::input(format!("{}: cannot write: {e}", out.display())))?;
            eprintln!("wrote {}", out.display());
        }
    }
    Ok(())
}
