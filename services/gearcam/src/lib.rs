//! The planning station: the `gearcam` command's library.
//!
//! # Layout
//!
//! - [`jobfile`]: TOML job files to [`gearcam_proto::JobSpec`], errors naming the key.
//! - [`check`]: the local pipeline (`gearcam check`) and its JSON contract.
//! - [`station`]: the client side: submitting a job to the station and following it.
//! - [`store`]: the client side of a machine's program store (history, versions, rollback).
//! - [`embedded`]: every service in one process on one session (`gearcam up`, `gearcam demo`).
#![forbid(unsafe_code)]

pub mod check;
pub mod embedded;
pub mod jobfile;
pub mod station;
pub mod store;

/// The endpoint `gearcam up` listens on and `gearcam submit` connects to by default.
pub const DEFAULT_ENDPOINT: &str = "tcp/127.0.0.1:7447";
