//! The behavioural L-system (thesis ch. 2.1, 6.2, appendices A and B):
//! definition files, postfix expressions, the step function S and context
//! matching. Knows nothing of geometry, physics or sound; what it needs of
//! them comes through [`Sensors`].

pub mod animation;
pub mod assist;
pub mod automata;
pub mod catalogue;
pub mod context;
pub mod definition;
pub mod eval;
pub mod expr;
pub mod functions;
pub mod infix;
pub mod limits;
pub mod options;
pub mod parse;
pub mod print;
pub mod readable;
pub mod readable_condition;
pub mod readable_writer;
pub mod scan;
pub mod sensors;
pub mod step;
pub mod thesis_form;
pub mod unparse;
pub mod word;

pub use crate::source::{Diagnostic, Source};
pub use animation::{Animation, LoadError};
pub use definition::Definition;
pub use limits::{LimitError, Limits};
pub use parse::parse;
pub use sensors::{FieldQuery, FieldValue, NoSensors, Sensors, Who};
pub use step::{Ephemeral, LSystem};
pub use word::Symbol;
