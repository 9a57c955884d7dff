//! The one error type of the crate.
//!
//! Every fallible core function returns [`BrdfError`]; the Python layer maps each variant
//! to one Python exception class in a single place (`py/mod.rs`), so bad input never
//! panics across the FFI boundary.

use std::fmt;

/// Which Python exception family an error belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorClass {
    /// A wrong value: out of range, NaN, bad shape (`ValueError`).
    Value,
    /// A wrong name or a missing argument (`TypeError`).
    Type,
    /// Memory that could not be allocated (`MemoryError`).
    Memory,
}

/// Everything that can go wrong in brdf-rs.
#[derive(Debug, Clone, PartialEq)]
pub enum BrdfError {
    /// The model name is not known.
    UnknownModel {
        name: String,
        suggestion: Option<String>,
        known: Vec<&'static str>,
    },
    /// A keyword parameter the model does not have.
    UnknownParameter {
        model: &'static str,
        name: String,
        suggestion: Option<String>,
        known: Vec<&'static str>,
    },
    /// A required parameter (or the tangent) was not given.
    MissingParameter {
        model: &'static str,
        name: &'static str,
    },
    /// A parameter value outside its valid range, or NaN.
    OutOfRange {
        name: String,
        value: f64,
        /// Index of the first bad element in the parameter's own array (empty for scalars).
        index: Vec<usize>,
        valid: String,
    },
    /// An input vector that is NaN, infinite or of zero length.
    BadVector {
        argument: &'static str,
        /// Index of the first bad vector in the argument's own array (batch axes only).
        index: Vec<usize>,
        problem: &'static str,
    },
    /// Shapes that do not fit together.
    Shape(String),
    /// Any other invalid argument (message says which and why).
    InvalidArgument(String),
    /// An allocation that failed (message says what and how large).
    OutOfMemory(String),
    /// The caller asked the work to stop (Ctrl-C); the binding raises its own exception.
    Interrupted,
}

impl BrdfError {
    /// The Python exception family of this error.
    pub fn class(&self) -> ErrorClass {
        match self {
            BrdfError::UnknownParameter { .. } | BrdfError::MissingParameter { .. } => {
                ErrorClass::Type
            }
            BrdfError::OutOfMemory(_) => ErrorClass::Memory,
            _ => ErrorClass::Value,
        }
    }
}

/// Returns a vector of `len` default values, or [`BrdfError::OutOfMemory`] naming `what`
/// when the memory is not there (`vec![x; len]` would abort the process instead).
pub fn try_filled_vec<T: Clone + Default>(len: usize, what: &str) -> Result<Vec<T>, BrdfError> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| {
        BrdfError::OutOfMemory(format!(
            "{what}: cannot allocate {len} elements of {} bytes",
            std::mem::size_of::<T>()
        ))
    })?;
    v.resize(len, T::default());
    Ok(v)
}

/// Formats an index as `[i, j]` (empty string for a scalar).
pub fn format_index(index: &[usize]) -> String {
    if index.is_empty() {
        String::new()
    } else {
        let parts: Vec<String> = index.iter().map(|i| i.to_string()).collect();
        format!("[{}]", parts.join(", "))
    }
}

/// Writes ` (did you mean "name"?)` after an unknown name that has a close match.
fn did_you_mean(f: &mut fmt::Formatter<'_>, suggestion: &Option<String>) -> fmt::Result {
    match suggestion {
        Some(s) => write!(f, " (did you mean {s:?}?)"),
        None => Ok(()),
    }
}

/// Formats a float the way Python prints it (`nan`, `inf`, `-1.0`, `1e-300`).
pub fn format_float(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        format!("{x:?}")
    }
}

/// Formats a shape the way NumPy prints it: `(3,)`, `(2, 3)`, `()`.
pub fn format_shape(shape: &[usize]) -> String {
    match shape.len() {
        0 => "()".to_string(),
        1 => format!("({},)", shape[0]),
        _ => {
            let parts: Vec<String> = shape.iter().map(|i| i.to_string()).collect();
            format!("({})", parts.join(", "))
        }
    }
}

impl fmt::Display for BrdfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BrdfError::UnknownModel {
                name,
                suggestion,
                known,
            } => {
                write!(f, "unknown model {name:?}")?;
                did_you_mean(f, suggestion)?;
                write!(f, "; known models: {}", known.join(", "))
            }
            BrdfError::UnknownParameter {
                model,
                name,
                suggestion,
                known,
            } => {
                write!(f, "{model}: unknown parameter {name:?}")?;
                did_you_mean(f, suggestion)?;
                if known.is_empty() {
                    write!(f, "; {model} takes no parameters")
                } else {
                    write!(f, "; {model} takes: {}", known.join(", "))
                }
            }
            BrdfError::MissingParameter { model, name } => {
                write!(f, "{model}: missing required parameter {name:?}")
            }
            BrdfError::OutOfRange {
                name,
                value,
                index,
                valid,
            } => {
                write!(
                    f,
                    "{name}{} = {} is out of range: must be {valid}",
                    format_index(index),
                    format_float(*value)
                )
            }
            BrdfError::BadVector {
                argument,
                index,
                problem,
            } => {
                let idx = format_index(index);
                if idx.is_empty() {
                    write!(f, "{argument} is {problem}")
                } else {
                    write!(f, "{argument}{idx} is {problem} (first bad index {idx})")
                }
            }
            BrdfError::Shape(msg)
            | BrdfError::InvalidArgument(msg)
            | BrdfError::OutOfMemory(msg) => f.write_str(msg),
            BrdfError::Interrupted => f.write_str("interrupted"),
        }
    }
}

impl std::error::Error for BrdfError {}

/// Suggests the closest of `known` to `name`, if any is close enough to be a typo.
pub fn closest<'a>(name: &str, known: &[&'a str]) -> Option<&'a str> {
    known
        .iter()
        .map(|k| (strsim::normalized_damerau_levenshtein(name, k), *k))
        .filter(|(score, _)| *score >= 0.6)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, k)| k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_find_typos_only() {
        let known = ["torrance_sparrow", "phong", "lambert"];
        assert_eq!(closest("torrance_sparow", &known), Some("torrance_sparrow"));
        assert_eq!(closest("lamber", &known), Some("lambert"));
        assert_eq!(closest("xyz", &known), None);
    }

    #[test]
    fn messages_name_the_argument_and_index() {
        let e = BrdfError::BadVector {
            argument: "wo",
            index: vec![2, 5],
            problem: "NaN",
        };
        assert_eq!(e.to_string(), "wo[2, 5] is NaN (first bad index [2, 5])");
        let e = BrdfError::OutOfRange {
            name: "p".into(),
            value: -1.0,
            index: vec![],
            valid: ">= 0".into(),
        };
        assert_eq!(e.to_string(), "p = -1.0 is out of range: must be >= 0");
        assert_eq!(format_shape(&[3]), "(3,)");
        assert_eq!(format_shape(&[2, 3]), "(2, 3)");
    }
}
