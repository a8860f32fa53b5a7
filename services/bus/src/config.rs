//! Bus configuration: the same settings for every gearcam program.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::BusError;

/// Zenoh session mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Peer: talks to peers directly and can listen.
    Peer,
    /// Client: connects to a router (or a listening peer).
    Client,
    /// Router: routes for clients and peers.
    Router,
}

impl Mode {
    fn as_str(self) -> &'static str {
        match self {
            Mode::Peer => "peer",
            Mode::Client => "client",
            Mode::Router => "router",
        }
    }
}

/// How a gearcam program joins the bus.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct BusConfig {
    /// A Zenoh JSON5 configuration file, applied first; the fields below override it.
    pub config_file: Option<PathBuf>,
    /// Session mode; `None` keeps the file's (or Zenoh's default, peer).
    pub mode: Option<Mode>,
    /// Endpoints to connect to, e.g. `tcp/127.0.0.1:7447`.
    pub connect: Vec<String>,
    /// Endpoints to listen on, e.g. `tcp/127.0.0.1:0`.
    pub listen: Vec<String>,
    /// Multicast scouting on or off; `None` keeps the file's (or Zenoh's default, on).
    pub multicast_scouting: Option<bool>,
}

impl BusConfig {
    /// A loopback configuration for tests and embedded use: peer mode,
    /// listening on the given endpoints, multicast scouting off.
    pub fn loopback(listen: &[&str]) -> BusConfig {
        BusConfig {
            mode: Some(Mode::Peer),
            listen: listen.iter().map(|s| s.to_string()).collect(),
            multicast_scouting: Some(false),
            ..BusConfig::default()
        }
    }

    /// A client connecting to the given endpoints, multicast scouting off.
    pub fn client(connect: &[String]) -> BusConfig {
        BusConfig {
            mode: Some(Mode::Client),
            connect: connect.to_vec(),
            multicast_scouting: Some(false),
            ..BusConfig::default()
        }
    }

    /// The user this configuration logs in as (`transport.auth.usrpwd.user`
    /// of its file), if it logs in.
    pub fn login(&self) -> Option<String> {
        let json = self
            .to_zenoh()
            .ok()?
            .get_json("transport/auth/usrpwd/user")
            .ok()?;
        serde_json::from_str::<Option<String>>(&json)
            .ok()
            .flatten()
            .filter(|u| !u.is_empty())
    }

    /// Builds the Zenoh configuration.
    pub fn to_zenoh(&self) -> Result<zenoh::Config, BusError> {
        let bad = |what: &str| {
            let what = what.to_string();
            move |e: zenoh::Error| BusError::Config {
                what,
                detail: e.to_string(),
            }
        };
        let mut c = match &self.config_file {
            Some(path) => {
                zenoh::Config::from_file(path).map_err(bad(&format!("file {}", path.display())))?
            }
            None => zenoh::Config::default(),
        };
        if let Some(mode) = self.mode {
            c.insert_json5("mode", &format!("{:?}", mode.as_str()))
                .map_err(bad("mode"))?;
        }
        if !self.connect.is_empty() {
            c.insert_json5("connect/endpoints", &json_list(&self.connect))
                .map_err(bad("connect/endpoints"))?;
        }
        if !self.listen.is_empty() {
            c.insert_json5("listen/endpoints", &json_list(&self.listen))
                .map_err(bad("listen/endpoints"))?;
        }
        if let Some(on) = self.multicast_scouting {
            c.insert_json5(
                "scouting/multicast/enabled",
                if on { "true" } else { "false" },
            )
            .map_err(bad("scouting/multicast/enabled"))?;
        }
        Ok(c)
    }
}

fn json_list(items: &[String]) -> String {
    let quoted: Vec<String> = items.iter().map(|s| format!("{s:?}")).collect();
    format!("[{}]", quoted.join(","))
}

/// An endpoint of the command line, checked before anything is opened:
/// `PROTOCOL/ADDRESS:PORT` with a protocol this build carries (`tcp`,
/// `quic` or `tls`). A wrong one is a usage error with this sentence, not a bus that
/// cannot be reached.
pub fn parse_endpoint(s: &str) -> Result<String, String> {
    let expected =
        "an endpoint PROTOCOL/ADDRESS:PORT, e.g. tcp/127.0.0.1:7447 or quic/planning-office:7447";
    let ep: zenoh::config::EndPoint = s
        .parse()
        .map_err(|_| format!("expected {expected}; got {s:?}"))?;
    let protocol = ep.protocol();
    let protocol = protocol.as_str();
    if !["tcp", "quic", "tls"].contains(&protocol) {
        return Err(format!(
            "expected {expected} (this build carries tcp, quic and tls); got the protocol {protocol:?} in {s:?}"
        ));
    }
    if !ep.address().as_str().contains(':') {
        return Err(format!(
            "expected {expected}: the port is missing; got {s:?}"
        ));
    }
    Ok(s.to_string())
}

/// Command-line arguments every gearcam program shares (after Zenoh's own
/// examples): `--config`, `--mode`, `--connect`, `--listen`, `--no-multicast-scouting`.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct BusArgs {
    /// Zenoh JSON5 configuration file (see deploy/).
    #[arg(long = "config", value_name = "FILE", env = "GEARCAM_ZENOH_CONFIG")]
    pub config: Option<PathBuf>,
    /// Zenoh session mode.
    #[arg(long, value_enum)]
    pub mode: Option<Mode>,
    /// Endpoint to connect to (repeatable), e.g. tcp/127.0.0.1:7447.
    #[arg(short = 'e', long = "connect", value_name = "ENDPOINT", value_parser = parse_endpoint)]
    pub connect: Vec<String>,
    /// Endpoint to listen on (repeatable), e.g. tcp/127.0.0.1:7447.
    #[arg(short = 'l', long = "listen", value_name = "ENDPOINT", value_parser = parse_endpoint)]
    pub listen: Vec<String>,
    /// Turn multicast scouting off (use only the given endpoints).
    #[arg(long)]
    pub no_multicast_scouting: bool,
}

impl BusArgs {
    /// The configuration these arguments describe.
    pub fn to_config(&self) -> BusConfig {
        BusConfig {
            config_file: self.config.clone(),
            mode: self.mode,
            connect: self.connect.clone(),
            listen: self.listen.clone(),
            multicast_scouting: self.no_multicast_scouting.then_some(false),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builds_a_zenoh_config_with_overrides() {
        let cfg = BusConfig {
            mode: Some(Mode::Client),
            connect: vec!["tcp/127.0.0.1:7447".into()],
            multicast_scouting: Some(false),
            ..BusConfig::default()
        };
        let z = cfg.to_zenoh().unwrap();
        let json = format!("{z}");
        assert!(json.contains("\"client\""), "{json}");
        assert!(json.contains("tcp/127.0.0.1:7447"), "{json}");
    }

    #[test]
    fn names_a_bad_endpoint() {
        let cfg = BusConfig {
            connect: vec!["not an endpoint".into()],
            ..BusConfig::default()
        };
        let err = cfg.to_zenoh().unwrap_err().to_string();
        assert!(err.contains("connect/endpoints"), "{err}");
    }

    #[test]
    fn names_a_missing_config_file() {
        let cfg = BusConfig {
            config_file: Some("/nonexistent/zenoh.json5".into()),
            ..BusConfig::default()
        };
        let err = cfg.to_zenoh().unwrap_err().to_string();
        assert!(err.contains("/nonexistent/zenoh.json5"), "{err}");
    }
}
