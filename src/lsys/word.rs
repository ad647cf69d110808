//! The evaluated symbol of an L-structure (table 2.1.1, figure 2.1.4).

/// One evaluated, timed, parametric symbol of a word.
///
/// The local age is `birth + ticks·Δt`, never a running float sum, so age
/// decisions are exact tick counts (DESIGN §3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Symbol {
    /// Unique identifier from the animation's global counter (2.1.3).
    pub id: u64,
    /// Age when the symbol was created (par0 at birth).
    pub birth: f64,
    /// par1..par3: x, y, z.
    pub par: [f64; 3],
    /// Index of its growth functions in the definition.
    pub growth: u32,
    /// Time steps lived.
    pub ticks: u32,
    pub ch: u8,
    /// Byte offset, in its L-system's file, of the axiom or right-side
    /// text that made it ([`NO_ORIGIN`] if none), so the turtle's
    /// warnings can name the line to fix. Fits the struct's padding.
    pub origin: u32,
}

/// [`Symbol::origin`] of a symbol no file text made.
pub const NO_ORIGIN: u32 = u32::MAX;

impl Symbol {
    /// par0, the local age, for a step of `dt`.
    #[inline]
    pub fn age(&self, dt: f64) -> f64 {
        self.birth + f64::from(self.ticks) * dt
    }

    /// A branch opening: `[` with par1 = 0 (other values address the
    /// turtle state tables and do not open a branch).
    #[inline]
    pub fn is_push(&self) -> bool {
        self.ch == b'[' && self.par[0] == 0.0
    }

    /// A branch closing: `]` with par1 = 0.
    #[inline]
    pub fn is_pop(&self) -> bool {
        self.ch == b']' && self.par[0] == 0.0
    }
}

/// Index of the `]` closing the branch that is open at `from` (the first
/// index inside it), or `None` when the word ends first.
pub fn branch_end(word: &[Symbol], from: usize) -> Option<usize> {
    let mut level = 0usize;
    for (k, s) in word.iter().enumerate().skip(from) {
        if s.is_push() {
            level += 1;
        } else if s.is_pop() {
            if level == 0 {
                return Some(k);
            }
            level -= 1;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_origin_fits_the_padding() {
        // Words are long: the source offset must not make symbols bigger.
        assert_eq!(std::mem::size_of::<super::Symbol>(), 56);
    }
}
