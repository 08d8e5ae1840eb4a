//! The approximation study (`approximations = [...]` in a matrix): which real-time
//! approximations each cell is rendered again without, so that the change in its error against
//! its truth and in its GPU time says what the approximation costs and what it saves.

/// One approximation the study replaces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Approximation {
    /// Order-2 SH ambient → the exact irradiance.
    Ambient,
    /// SH ambient + split-sum probe → the environment integrated over the model's BRDF.
    Environment,
    /// Shadow maps → ray-traced visibility.
    Visibility,
    /// The cell's MSAA level → each other level.
    Msaa,
}

impl Approximation {
    pub const ALL: [Approximation; 4] =
        [Approximation::Ambient, Approximation::Environment, Approximation::Visibility, Approximation::Msaa];

    pub fn name(self) -> &'static str {
        match self {
            Approximation::Ambient => "ambient",
            Approximation::Environment => "environment",
            Approximation::Visibility => "visibility",
            Approximation::Msaa => "msaa",
        }
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|a| a.name()).collect()
    }

    pub fn from_name(name: &str) -> Option<Approximation> {
        Self::ALL.into_iter().find(|a| a.name() == name)
    }
}
