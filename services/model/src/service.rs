//! Zenoh wrapper (written separately).
