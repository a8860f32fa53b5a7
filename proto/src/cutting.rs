//! What the part families share about cutting.

use serde::{Deserialize, Serialize};

/// Cutting mode: climb or conventional (hobbing and milling alike).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CutMode {
    /// Conventional cutting: the hob feeds against the workpiece rotation (patent default; feeds down).
    Conventional,
    /// Climb cutting: the hob feeds with the workpiece rotation (feeds up).
    Climb,
}
