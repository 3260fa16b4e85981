//! The runtime's error type: why a bundle cannot be played.

use core::fmt;

use taxel_format::{Family, FormatError, ProfileName, Tag};

/// Why a player refused a bundle. Everything here is decided when the player
/// is built; once built, a player never fails.
#[derive(Debug, Clone, PartialEq)]
pub enum RuntimeError {
    /// The bundle was compiled for a device of another family.
    WrongFamily {
        /// The family this player drives.
        expected: Family,
        /// The family of the bundle's profile.
        found: Family,
        /// The name of the bundle's profile.
        profile: ProfileName,
    },
    /// The bundle is not a valid taxel bundle.
    Format(FormatError),
    /// The bundle holds a chunk this family's player cannot play.
    UnexpectedChunk {
        /// The family of the player.
        family: Family,
        /// The chunk's tag.
        tag: Tag,
    },
    /// The bundle has more layers than the storage given to the player.
    TooManyLayers {
        /// Layers in the bundle.
        needed: usize,
        /// Layers the storage holds.
        capacity: usize,
    },
    /// The profile asks for something this player does not support.
    Unsupported {
        /// The profile field.
        field: &'static str,
        /// Its value.
        value: u32,
        /// The largest value this player supports.
        limit: u32,
    },
}

impl fmt::Display for RuntimeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RuntimeError::WrongFamily { expected, found, profile } => write!(
                f,
                "the bundle was compiled for profile `{profile}` ({found} family), \
                 but this player drives the {expected} family"
            ),
            RuntimeError::Format(e) => write!(f, "invalid bundle: {e}"),
            RuntimeError::UnexpectedChunk { family, tag } => {
                write!(f, "a {family} bundle cannot hold a {tag} chunk")
            }
            RuntimeError::TooManyLayers { needed, capacity } => write!(
                f,
                "the bundle has {needed} layers but the player's storage holds {capacity}: \
                 give the player larger storage"
            ),
            RuntimeError::Unsupported { field, value, limit } => {
                write!(f, "profile {field} is {value}, but this player supports at most {limit}")
            }
        }
    }
}

impl From<FormatError> for RuntimeError {
    fn from(e: FormatError) -> Self {
        RuntimeError::Format(e)
    }
}

#[cfg(feature = "std")]
impl std::error::Error for RuntimeError {}
