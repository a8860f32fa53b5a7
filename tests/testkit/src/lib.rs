//! Test support shared by every crate's tests, so that no test keeps its own
//! copy of a fixture:
//!
//! - [`examples`]: the example job files of `examples/` (valid and invalid),
//!   and a job moved to another machine.
//! - [`pipeline`]: a job's request, plan, model and program in this process,
//!   through the seeded knowledge base, the model and the shipped templates;
//!   the seeded machines as the knowledge base seeds them.
//! - [`process`]: the built binaries as processes on loopback (a router,
//!   every service, an agent), each in a temporary directory, on ports the
//!   operating system chose.
//! - [`flood`]: an authenticated planner's bursts of concurrent queries.
//! - [`secure`]: the secure deployment of `deploy/secure/` as processes.
// Test code: clocks for timeouts, the environment for switches.
#![allow(clippy::disallowed_methods)]
#![forbid(unsafe_code)]

pub mod examples;
pub mod flood;
pub mod pipeline;
pub mod process;
pub mod secure;
pub mod web;

pub use process::{
    bin, client_config, gearcam, start_web, wait_for_port, web_password, web_users, Cluster, Proc,
};
