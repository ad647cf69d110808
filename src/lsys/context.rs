//! (1,1) context matching (codes 2.1.2 and 2.1.3).
//!
//! Symbols that draw nothing are skipped: `+ - / $ ^ & m n` and the state
//! table forms of `[ ]` (par1 ≠ 0). The left context is searched on the
//! path to the root; the right context in the following sub-trees.

use super::word::Symbol;

#[inline]
fn ignored(s: &Symbol) -> bool {
    matches!(s.ch, b'+' | b'-' | b'/' | b'$' | b'^' | b'&' | b'm' | b'n')
        || (matches!(s.ch, b'[' | b']') && s.par[0] != 0.0)
}

/// Code 2.1.2: is `want` the left neighbour of `word[i]`?
///
/// The printed loop lowers `level` below zero at the `[` opening the
/// current branch, which would skip the branch's parent; here that `[` is
/// passed at level 0 so the search continues with the parent, as
/// [PRUS90] defines the left context.
pub fn left_matches(word: &[Symbol], i: usize, want: u8) -> bool {
    let mut level = 0usize;
    for s in word[..i].iter().rev() {
        if s.is_pop() {
            level += 1;
        } else if s.is_push() {
            level = level.saturating_sub(1);
        } else if level == 0 && !ignored(s) {
            return s.ch == want;
        }
    }
    false
}

/// Code 2.1.3: is `want` a right neighbour of `word[i]`, in the following
/// branch or any sub-tree starting there?
///
/// Written as a loop with an explicit stack of entered sub-trees, so deep
/// nesting cannot overflow the call stack. As in the thesis, a `]` that
/// ends the current branch is passed and the search goes on after it.
pub fn right_matches(word: &[Symbol], i: usize, want: u8) -> bool {
    let mut open = 0usize; // sub-trees entered
    let mut j = i + 1;
    while j < word.len() {
        let s = &word[j];
        if s.is_push() {
            open += 1;
            j += 1;
        } else if s.is_pop() {
            open = open.saturating_sub(1);
            j += 1;
        } else if ignored(s) {
            j += 1;
        } else if s.ch == want {
            return true;
        } else if open > 0 {
            // This sub-tree failed: go on after its end.
            match super::word::branch_end(word, j) {
                Some(end) => {
                    open -= 1;
                    j = end + 1;
                }
                None => return false,
            }
        } else {
            return false;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn word(s: &str) -> Vec<Symbol> {
        s.bytes()
            .map(|ch| Symbol {
                id: 0,
                birth: 0.0,
                par: [0.0; 3],
                growth: 0,
                ticks: 0,
                ch,
                origin: 0,
            })
            .collect()
    }

    #[test]
    fn left_context_follows_path_to_root() {
        let w = word("A[B]+C");
        assert!(left_matches(&w, 5, b'A')); // C: skips [B] and +
        assert!(left_matches(&w, 2, b'A')); // B inside the branch
        assert!(!left_matches(&w, 0, b'A'));
    }

    #[test]
    fn right_context_searches_subtrees() {
        let w = word("A+$B");
        assert!(right_matches(&w, 0, b'B'));
        let w = word("A[+-B]C");
        assert!(right_matches(&w, 0, b'B'));
        assert!(right_matches(&w, 0, b'C')); // B fails, C follows the branch
        let w = word("A[+-D]+-C");
        assert!(right_matches(&w, 0, b'C'));
        assert!(right_matches(&w, 0, b'D'));
        let w = word("A+$]B");
        assert!(right_matches(&w, 0, b'B'));
        assert!(!right_matches(&word("A+$C"), 0, b'B'));
    }
}
