//! A readable file spelt in the thesis's own classic form (issue 40's
//! `convert`): every expression in postfix, as appendix A writes it.

use super::expr::{Code, Compiler};
use super::parse::parse;
use super::readable::to_classic_with;
use super::unparse::postfix;
use crate::source::{Diagnostic, Source};

/// The classic text of the readable file `src`, expressions in postfix.
pub fn to_thesis(src: &Source) -> Result<String, Diagnostic> {
    let def = parse(src)?;
    let splines: Vec<u32> = def.splines.iter().map(|s| s.number).collect();
    let constant_r = def.constants.defined(b'r');
    let respell = |infix: &str| {
        let text = Source::new("", infix);
        let mut code = Code::default();
        let mut c = Compiler {
            src: &text,
            code: &mut code,
            constants: &def.constants,
            splines: &splines,
        };
        let mut em = c.begin();
        c.infix(&mut em, infix, 0).ok()?;
        postfix(&code.ops, constant_r)
    };
    Ok(to_classic_with(src, Some(&respell))?.text)
}
