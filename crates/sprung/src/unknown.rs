//! The error of every `FromStr` of a named choice (an integrator, a
//! device, a frame format, a plot's scale): the name given and the names
//! known, so the message lists what would have been accepted.

/// A name that is none of the values a choice takes.
///
/// ```
/// use sprung::{IntegratorKind, UnknownName};
///
/// let error: UnknownName = "leapfrog".parse::<IntegratorKind>().unwrap_err();
/// assert_eq!(error.what, "integrator");
/// assert_eq!(error.name, "leapfrog");
/// assert!(error.to_string().starts_with("unknown integrator \"leapfrog\" (known: euler, "));
/// ```
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown {what} \"{name}\" (known: {})", known.join(", "))]
pub struct UnknownName {
    /// What was being named ("integrator", "device", "frame format").
    pub what: &'static str,
    /// The name given.
    pub name: String,
    /// Every name the choice accepts, in the order they are listed.
    pub known: Vec<&'static str>,
}

impl UnknownName {
    /// The error for `name`, which is none of `known`.
    pub fn new(
        what: &'static str,
        name: &str,
        known: impl IntoIterator<Item = &'static str>,
    ) -> Self {
        UnknownName {
            what,
            name: name.to_owned(),
            known: known.into_iter().collect(),
        }
    }
}
