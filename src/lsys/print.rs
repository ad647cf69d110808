//! The thesis's PRINT option: a word as text.

use super::sensors::Sensors;
use super::step::{ActorScope, LSystem};

/// How a word is printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Only the symbol characters.
    Symbols,
    /// `X(age,x,y,z,f1,f2,f3)` per symbol, growth functions evaluated.
    Full,
}

/// A value with at most 6 decimals, trailing zeros trimmed.
pub fn number(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        &s
    };
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// The word of `ls` at global time `time`.
pub fn word(
    ls: &mut LSystem,
    format: Format,
    time: f64,
    seed: u64,
    sensors: &mut dyn Sensors,
) -> String {
    match format {
        Format::Symbols => ls.word().iter().map(|s| s.ch as char).collect(),
        Format::Full => {
            let symbols = ls.word().to_vec();
            let mut out = String::with_capacity(symbols.len() * 24);
            let mut scope = ActorScope::default();
            for (k, s) in symbols.iter().enumerate() {
                if k > 0 {
                    out.push(' ');
                }
                let g = ls.growth(s, time, scope.visit(s), seed, sensors);
                let v = [s.age(ls.dt), s.par[0], s.par[1], s.par[2], g[0], g[1], g[2]];
                out.push(s.ch as char);
                out.push('(');
                for (j, x) in v.iter().enumerate() {
                    if j > 0 {
                        out.push(',');
                    }
                    out.push_str(&number(*x));
                }
                out.push(')');
            }
            out
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn numbers_are_trimmed() {
        assert_eq!(super::number(6.5), "6.5");
        assert_eq!(super::number(2.0), "2");
        assert_eq!(super::number(-0.0000001), "0");
        assert_eq!(super::number(1.0 / 3.0), "0.333333");
        assert_eq!(super::number(1e30), "1000000000000000019884624838656");
    }
}
