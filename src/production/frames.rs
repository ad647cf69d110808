//! Which frames a process renders and what their files are called
//! (DESIGN §5): `--frames A..B`, the thesis option `rs_switch`, render-farm
//! shards `--shard K/N`, and the numbered paths inside the output folder.
//!
//! Frame numbers are 0-based; frame n shows time n·Δt. Ranges follow Rust's
//! notation: `A..B` is A up to but excluding B, `A..=B` includes B.

use std::fmt;
use std::ops::Range;
use std::str::FromStr;

/// The forms `--frames` accepts, quoted by every range error.
const RANGE_FORMS: &str = "write `A..B` (frames A to B-1), `A..=B` (A to B inclusive), \
                           `A..` (A to the end) or `N` (frame N alone), e.g. `0..250`";

/// A contiguous run of frames, `start` included, `end` excluded
/// (`None`: up to the end of the film).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameRange {
    pub start: u64,
    pub end: Option<u64>,
}

/// Why a `--frames` argument was refused; the message says what to write.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RangeError {
    /// Not of the form `A..B`, `A..=B`, `A..` or `N`.
    Syntax { text: String },
    /// A bound is not a whole non-negative number (or is too large).
    Number { text: String, bound: String },
    /// The range is well formed but holds no frame (`5..5`, `7..=3`).
    Empty { text: String },
}

impl fmt::Display for RangeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RangeError::Syntax { text } => {
                write!(f, "cannot read frame range `{text}`: {RANGE_FORMS}")
            }
            RangeError::Number { text, bound } => write!(
                f,
                "frame range `{text}`: `{bound}` is not a frame number (frames are \
                 0-based whole numbers); {RANGE_FORMS}"
            ),
            RangeError::Empty { text } => write!(
                f,
                "frame range `{text}` selects no frame: in `A..B` the end B is excluded \
                 and must be greater than A, in `A..=B` B must be at least A"
            ),
        }
    }
}

impl std::error::Error for RangeError {}

impl FrameRange {
    /// Whether `frame` lies in the range.
    pub fn contains(&self, frame: u64) -> bool {
        frame >= self.start && !matches!(self.end, Some(end) if frame >= end)
    }

    /// The frames of the range that exist in a film of `frame_count` frames.
    pub fn within(&self, frame_count: u64) -> Range<u64> {
        let end = self.end.map_or(frame_count, |e| e.min(frame_count));
        self.start.min(end)..end
    }
}

impl fmt::Display for FrameRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.end {
            Some(end) => write!(f, "{}..{end}", self.start),
            None => write!(f, "{}..", self.start),
        }
    }
}

impl FromStr for FrameRange {
    type Err = RangeError;

    /// Reads `A..B`, `A..=B`, `A..` or `N`; a missing A means 0.
    fn from_str(text: &str) -> Result<Self, RangeError> {
        let trimmed = text.trim();
        let number = |bound: &str| match bound.trim() {
            "" => Err(RangeError::Syntax {
                text: text.to_string(),
            }),
            b => b.parse::<u64>().map_err(|_| RangeError::Number {
                text: text.to_string(),
                bound: b.to_string(),
            }),
        };
        let start_of = |a: &str| {
            if a.trim().is_empty() {
                Ok(0)
            } else {
                number(a)
            }
        };
        let (start, end) = if let Some((a, b)) = trimmed.split_once("..=") {
            let last = number(b)?;
            let end = last.checked_add(1).ok_or_else(|| RangeError::Number {
                text: text.to_string(),
                bound: b.trim().to_string(),
            })?;
            (start_of(a)?, Some(end))
        } else if let Some((a, b)) = trimmed.split_once("..") {
            let end = if b.trim().is_empty() {
                None
            } else {
                Some(number(b)?)
            };
            (start_of(a)?, end)
        } else if trimmed.bytes().all(|c| c.is_ascii_digit()) && !trimmed.is_empty() {
            let n = number(trimmed)?;
            (n, n.checked_add(1))
        } else {
            return Err(RangeError::Syntax {
                text: text.to_string(),
            });
        };
        if end.is_some_and(|e| e <= start) {
            return Err(RangeError::Empty {
                text: text.to_string(),
            });
        }
        Ok(FrameRange { start, end })
    }
}

/// One of N render processes (`--shard K/N`, 1 ≤ K ≤ N). Frame f belongs
/// to shard (f mod N) + 1: round robin, so the expensive late frames of a
/// growing scene are spread over all processes rather than piled on the last.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    index: u64,
    count: u64,
}

/// Why a `--shard` argument was refused; the message says what to write.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ShardError {
    /// Not of the form `K/N`.
    Syntax { text: String },
    /// K or N is not a whole non-negative number.
    Number { text: String, part: String },
    /// N is 0, or K is not between 1 and N.
    OutOfRange { index: u64, count: u64 },
}

impl fmt::Display for ShardError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ShardError::Syntax { text } => write!(
                f,
                "cannot read shard `{text}`: write `K/N` for the K-th of N render \
                 processes, e.g. `--shard 2/4`"
            ),
            ShardError::Number { text, part } => write!(
                f,
                "shard `{text}`: `{part}` is not a whole number; write `K/N`, e.g. `2/4`"
            ),
            ShardError::OutOfRange { count: 0, .. } => {
                f.write_str("shard count N must be at least 1: `K/N` with 1 <= K <= N, e.g. `1/1`")
            }
            ShardError::OutOfRange { index, count } => write!(
                f,
                "shard {index}/{count}: K counts from 1 to N, so write one of 1/{count} \
                 … {count}/{count}"
            ),
        }
    }
}

impl std::error::Error for ShardError {}

impl Shard {
    /// The K-th of N shards, counting from 1.
    pub fn new(index: u64, count: u64) -> Result<Shard, ShardError> {
        if count == 0 || index == 0 || index > count {
            return Err(ShardError::OutOfRange { index, count });
        }
        Ok(Shard { index, count })
    }

    /// The single shard `1/1`: one process renders everything.
    pub fn all() -> Shard {
        Shard { index: 1, count: 1 }
    }

    /// K, counting from 1.
    pub fn index(&self) -> u64 {
        self.index
    }

    /// N, the number of processes.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Whether this shard renders `frame`.
    pub fn contains(&self, frame: u64) -> bool {
        frame % self.count + 1 == self.index
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = ShardError;

    fn from_str(text: &str) -> Result<Self, ShardError> {
        let (k, n) = text
            .trim()
            .split_once('/')
            .ok_or_else(|| ShardError::Syntax {
                text: text.to_string(),
            })?;
        let number = |part: &str| {
            part.trim().parse::<u64>().map_err(|_| ShardError::Number {
                text: text.to_string(),
                part: part.trim().to_string(),
            })
        };
        Shard::new(number(k)?, number(n)?)
    }
}

/// The frames to render: a union of ranges, before the film's length and
/// the shard are applied.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameSelection {
    ranges: Vec<FrameRange>,
}

impl FrameSelection {
    /// Every frame of the film.
    pub fn all() -> FrameSelection {
        FrameSelection::range(FrameRange {
            start: 0,
            end: None,
        })
    }

    /// The frames of one range.
    pub fn range(range: FrameRange) -> FrameSelection {
        FrameSelection {
            ranges: vec![range],
        }
    }

    /// The thesis option `rs_switch min1 max1 min2 max2 min3 max3`: up to
    /// three intervals, both ends included. A lone trailing number selects
    /// that frame; an interval with max < min or max < 0 selects nothing
    /// (a way to switch it off), and negative mins count from frame 0.
    pub fn from_rs_switch(values: &[i64]) -> FrameSelection {
        let ranges = values
            .chunks(2)
            .filter_map(|pair| {
                let (min, max) = (pair[0], *pair.last()?);
                let last = u64::try_from(max).ok()?;
                let start = u64::try_from(min.max(0)).ok()?;
                (start <= last).then(|| FrameRange {
                    start,
                    end: last.checked_add(1),
                })
            })
            .collect();
        FrameSelection { ranges }
    }

    /// The command line's `--frames` overrides the scene's `rs_switch`;
    /// with neither, every frame.
    pub fn resolve(cli: Option<FrameRange>, rs_switch: Option<&[i64]>) -> FrameSelection {
        match (cli, rs_switch) {
            (Some(range), _) => FrameSelection::range(range),
            (None, Some(values)) => FrameSelection::from_rs_switch(values),
            (None, None) => FrameSelection::all(),
        }
    }

    /// The ranges as text (`A..B`, `A..`), as records keep them.
    pub fn to_text(&self) -> Vec<String> {
        self.ranges.iter().map(FrameRange::to_string).collect()
    }

    /// The selection of [`FrameSelection::to_text`]'s ranges.
    pub fn from_text(ranges: &[String]) -> Result<FrameSelection, RangeError> {
        let ranges = ranges.iter().map(|r| r.parse()).collect::<Result<_, _>>()?;
        Ok(FrameSelection { ranges })
    }

    /// Whether `frame` is selected (regardless of the film's length).
    pub fn contains(&self, frame: u64) -> bool {
        self.ranges.iter().any(|r| r.contains(frame))
    }

    /// The selected frames of a film of `frame_count` frames that `shard`
    /// renders, in increasing order, each once.
    pub fn frames(&self, frame_count: u64, shard: Shard) -> Vec<u64> {
        let mut frames: Vec<u64> = self
            .ranges
            .iter()
            .flat_map(|r| r.within(frame_count))
            .filter(|&f| shard.contains(f))
            .collect();
        frames.sort_unstable();
        frames.dedup();
        frames
    }
}
