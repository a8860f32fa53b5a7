//! The one place that decides how a `gearcam` command joins the bus: the
//! embedded services (`up`, `demo`) as a listening peer, a client (`submit`,
//! `jobs`, `status`, `program`, `station`) connecting to the local `gearcam
//! up` unless told otherwise, and the router. A Zenoh configuration file
//! (`--config`) is always taken as it is.

use std::path::PathBuf;

use gearcam_bus::{BusArgs, BusConfig, Mode};

use crate::DEFAULT_ENDPOINT;

/// The embedded services: a peer listening on `default_listen` unless told
/// otherwise, multicast scouting off.
pub fn embedded(bus: &BusArgs, default_listen: &str) -> BusConfig {
    let mut c = bus.to_config();
    c.mode.get_or_insert(Mode::Peer);
    if c.listen.is_empty() && c.config_file.is_none() {
        c.listen = vec![default_listen.to_string()];
    }
    if c.config_file.is_none() {
        c.multicast_scouting = Some(false);
    }
    c
}

/// A client: the given endpoints, or the local `gearcam up`; multicast
/// scouting off.
pub fn client(bus_args: &BusArgs) -> BusConfig {
    let mut config = bus_args.to_config();
    if config.connect.is_empty() && config.config_file.is_none() {
        config.connect = vec![DEFAULT_ENDPOINT.to_string()];
    }
    if config.config_file.is_none() {
        config.mode.get_or_insert(Mode::Client);
        config.multicast_scouting.get_or_insert(false);
    }
    config
}

/// A service on its own (`gearcam station`): as given when it names an
/// endpoint or a configuration file, else a client of the local `gearcam up`.
pub fn service(bus_args: &BusArgs) -> BusConfig {
    let config = bus_args.to_config();
    if config.config_file.is_none() && config.connect.is_empty() && config.listen.is_empty() {
        client(bus_args)
    } else {
        config
    }
}

/// The router: router mode, multicast scouting off unless a configuration
/// file says otherwise.
pub fn router(bus_args: &BusArgs) -> BusConfig {
    let mut config = bus_args.to_config();
    if config.config_file.is_none() {
        config.mode = Some(Mode::Router);
        config.multicast_scouting.get_or_insert(false);
    }
    config
}

/// The bus options of a client command (`submit`, `jobs`, `status`,
/// `program`): where the router or `gearcam up` is, or a configuration file.
/// Only what a client uses: no `--listen`, no `--mode`.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct ClientArgs {
    /// Zenoh JSON5 configuration file (see deploy/, e.g. TLS and a user).
    #[arg(long = "config", value_name = "FILE", env = "GEARCAM_ZENOH_CONFIG")]
    pub config: Option<PathBuf>,
    /// The router or `gearcam up` to connect to (repeatable; default tcp/127.0.0.1:7447).
    #[arg(short = 'e', long = "connect", value_name = "ENDPOINT", value_parser = gearcam_bus::config::parse_endpoint)]
    pub connect: Vec<String>,
}

impl ClientArgs {
    /// As the shared bus arguments (client mode is decided by [`client`]).
    pub fn bus_args(&self) -> BusArgs {
        BusArgs {
            config: self.config.clone(),
            connect: self.connect.clone(),
            ..BusArgs::default()
        }
    }
}
