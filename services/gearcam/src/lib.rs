//! The `gearcam` command's library: the command line, one module per command,
//! and the client side of the planning station and the program stores.
//!
//! # Layout
//!
//! - [`cli`]: the arguments and the dispatch; [`cmd`]: one module per command.
//! - [`bus_config`]: the one place that decides how a command joins the bus.
//! - [`exit`]: the exit codes, one meaning each.
//! - [`examples`]: the example jobs bundled into the binary.
//! - [`output`]: standard output that survives a closed pipe.
//! - [`jobfile`]: TOML job files to [`gearcam_proto::JobSpec`], errors naming the key.
//! - [`check`]: the local pipeline (`gearcam check`) and its JSON contract.
//! - [`station`]: the client side: submitting a job to the station and following it.
//! - [`store`]: the client side of a machine's program store (history, versions, rollback).
//! - [`web`]: the planning office's page (`gearcam web`), a client of the bus.
//! - [`embedded`]: every service in one process on one session (`gearcam up`, `gearcam demo`).
#![forbid(unsafe_code)]

pub mod bus_config;
pub mod check;

pub mod cli;
pub mod cmd;
pub mod data_dir;
pub mod embedded;
pub mod examples;
pub mod exit;
pub mod jobfile;
pub mod output;
pub mod station;
pub mod store;
pub mod web;

/// The endpoint `gearcam up` listens on and `gearcam submit` connects to by default.
pub const DEFAULT_ENDPOINT: &str = "tcp/127.0.0.1:7447";
