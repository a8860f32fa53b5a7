//! Virtual hobbing: run a hobbing program on a kinematic model of the
//! machine and cut a virtual blank with the hob's cutting edges.
//!
//! The program is read back by `gearcam_nc::check`; its [`gearcam_nc::Trace`]
//! (every move, every gearbox-on block, the spindle speeds and swivel angles)
//! and the machining model's hob and machine data give the hob's pose relative
//! to the workpiece as a function of time ([`kinematics::Timeline`]). The
//! hob's gashes ([`hob::Hob`]) pass the blank once per hob turn each; every
//! pass removes material from the blank's transverse sections
//! ([`cut::Blank`]). Generating flats and feed marks come out of the
//! discrete passes by themselves. The conventions and the closed forms the
//! tests check are written down in `docs/simulation.md`.
//!
//! # Layout
//!
//! - [`kinematics`]: the machine-neutral axes (X, Y, Z, η, B, C) over time,
//!   from a trace or from segments built by hand.
//! - [`hob`]: the hob's cutting edges: the axial (rake-plane) tooth profile of
//!   each gash.
//! - [`cut`]: the blank as polar outlines on z planes and the material
//!   removal.
//! - [`safety`]: collisions, cutting without the gearbox, depth, face width,
//!   shift compensation and synchronisation, from the same timeline.

#![forbid(unsafe_code)]

pub mod cut;
pub mod hob;
pub mod kinematics;
pub mod safety;
pub mod simulate;

/// What stops a program from being simulated.
#[derive(Debug, Clone, PartialEq)]
pub enum SimError {
    /// The trace has no move to simulate.
    Empty,
    /// A coupling's ratio has a zero denominator (line).
    BadRatio(u32),
    /// A feed move without a positive feed rate (line).
    NoFeed(u32),
    /// A parameter is out of its range: its name and why.
    Parameter(&'static str, &'static str),
}

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SimError::Empty => write!(f, "the trace has no move to simulate"),
            SimError::BadRatio(l) => write!(f, "line {l}: gearbox ratio with a zero denominator"),
            SimError::NoFeed(l) => write!(f, "line {l}: feed move without a positive feed rate"),
            SimError::Parameter(n, why) => write!(f, "parameter {n}: {why}"),
        }
    }
}

impl std::error::Error for SimError {}
