//! The secure deployment of `deploy/secure/` as processes on loopback: a
//! router with its link's certificates, a user and password per service and
//! the access control (default deny), every service as its own process with
//! its own user, and the agents of H01 (840D), H02 (FANUC) and W01 (wire
//! 3B/4B).
//!
//! The configurations are the shipped files with their paths made local and
//! the router's port the one the operating system chose. The link is the
//! shipped one; `GEARCAM_SECURE_LINK=tls` runs the same deployment over
//! TLS instead (the link it replaced), to show what a test catches there.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use crate::process::Proc;

/// The log target of Zenoh's access control: at `trace` it logs every
/// decision, a refusal as `… on {subject} is unauthorized to {action} on {key}`.
const ACL_LOG: &str = "zenoh::net::routing::interceptor::access_control";

/// How many decisions the router makes ahead when it caches a key: one per
/// kind of message (query, reply, put, delete, subscriber, queryable,
/// liveliness token, liveliness query, liveliness subscriber).
const CACHED_KINDS: usize = 9;

/// `deploy/secure/` of the checkout.
pub fn deploy() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../deploy/secure")
}

/// The link the deployment runs on: `quic` as shipped, or the one named by
/// `GEARCAM_SECURE_LINK`.
pub fn link() -> String {
    std::env::var("GEARCAM_SECURE_LINK").unwrap_or_else(|_| SHIPPED_LINK.to_string())
}

/// The link `deploy/secure/` ships.
pub const SHIPPED_LINK: &str = "quic";

/// Copies the deploy configuration `name` into `dir` with its paths, link
/// and port made local.
pub fn local_config(dir: &Path, name: &str, port: u16) -> PathBuf {
    let text = std::fs::read_to_string(deploy().join(name)).expect("a deploy configuration");
    let link = link();
    let text = text
        .replace("/etc/gearcam/", &format!("{}/", dir.display()))
        .replace(
            &format!("{SHIPPED_LINK}/0.0.0.0:7447"),
            &format!("{link}/127.0.0.1:{port}"),
        )
        .replace(
            &format!("{SHIPPED_LINK}/localhost:7447"),
            &format!("{link}/localhost:{port}"),
        );
    let path = dir.join(name);
    std::fs::write(&path, text).expect("a local configuration");
    path
}

/// The secure deployment's processes in a temporary directory.
#[derive(Debug)]
pub struct Secure {
    tmp: tempfile::TempDir,
    /// The router's port.
    pub port: u16,
    /// The router, the services and the agents.
    pub procs: Vec<Proc>,
}

impl Secure {
    /// Makes the certificates, starts the router and waits for its port,
    /// then starts every service and the agents of H01, H02 and W01.
    pub fn start() -> Secure {
        Secure::start_with("info", "fine")
    }

    /// [`Secure::start`] with the template service's `--simulation` mode
    /// (`fine`, its default, `coarse` or `off`).
    pub fn start_simulating(simulation: &str) -> Secure {
        Secure::start_with("info", simulation)
    }

    /// [`Secure::start`] with the router logging every decision of its
    /// access control, so that [`Secure::denials`] lists what it refused.
    pub fn start_auditing() -> Secure {
        Secure::start_with(&format!("info,{ACL_LOG}=trace"), "fine")
    }

    fn start_with(router_log: &str, simulation: &str) -> Secure {
        let tmp = tempfile::tempdir().expect("temp dir");
        let dir = tmp.path();
        let made = Command::new("bash")
            .arg(deploy().join("make-certs.sh"))
            .arg(dir)
            .output()
            .expect("bash runs make-certs.sh");
        assert!(
            made.status.success(),
            "make-certs.sh: {}",
            String::from_utf8_lossy(&made.stderr)
        );
        std::fs::copy(deploy().join("users.txt"), dir.join("users.txt")).expect("users.txt");
        let router = local_config(dir, "router.json5", 0);
        let router = Proc::start_logging(
            dir,
            "router",
            "gearcam",
            &strings(&["router", "--config", &router.display().to_string()]),
            router_log,
        );
        let port = router.listening_port(Duration::from_secs(20));
        // The router's configuration names the port it got, so that a router
        // killed and started again listens where the clients look for it.
        local_config(dir, "router.json5", port);
        let mut secure = Secure {
            tmp,
            port,
            procs: vec![router],
        };
        let (journal, db, templates) = (
            secure.path("station.db"),
            secure.path("kb.db"),
            secure.path("templates.db"),
        );
        secure.start_service("station", "gearcam", &["station", "--journal", &journal]);
        secure.start_service("knowledge", "gearcam-knowledge", &["--db", &db]);
        secure.start_service("model", "gearcam-model", &[]);
        secure.start_service(
            "template",
            "gearcam-template",
            &["--library", &templates, "--simulation", simulation],
        );
        secure.start_agent("H01", "sinumerik840d");
        secure.start_agent("H02", "fanuc");
        secure.start_agent("W01", "wire3b");
        secure
    }

    /// Starts `bin` labelled `label` with the configuration `{label}.json5`
    /// and `args`.
    fn start_service(&mut self, label: &str, bin: &str, args: &[&str]) {
        let cfg = self.cfg(label).display().to_string();
        let mut all: Vec<&str> = Vec::new();
        // `gearcam station` takes its subcommand first.
        let (sub, rest) = match args.split_first() {
            Some((first, rest)) if bin == "gearcam" => (vec![*first], rest),
            _ => (Vec::new(), args),
        };
        all.extend(sub);
        all.extend(["--config", &cfg]);
        all.extend(rest);
        let proc = Proc::start(self.dir(), label, bin, &strings(&all));
        self.procs.push(proc);
    }

    /// Starts the agent of `machine` (a `dialect` control) with its own user,
    /// labelled `agent` for H01 and `agent-{machine}` otherwise, its store
    /// under `{machine}/`.
    pub fn start_agent(&mut self, machine: &str, dialect: &str) {
        let label = if machine == "H01" {
            "agent".to_string()
        } else {
            format!("agent-{machine}")
        };
        let cfg = self.cfg(&format!("agent-{machine}")).display().to_string();
        let (programs, index) = (
            self.path(&format!("{machine}/programs")),
            self.path(&format!("{machine}/index.db")),
        );
        let args = strings(&[
            "--config",
            &cfg,
            "--machine",
            machine,
            "--dialect",
            dialect,
            "--program-dir",
            &programs,
            "--index",
            &index,
        ]);
        let proc = Proc::start(self.dir(), &label, "gearcam-agent", &args);
        self.procs.push(proc);
    }

    /// The deployment's directory (certificates, databases, stores, logs).
    pub fn dir(&self) -> &Path {
        self.tmp.path()
    }

    fn path(&self, name: &str) -> String {
        self.dir().join(name).display().to_string()
    }

    /// The process labelled `label`.
    pub fn proc(&mut self, label: &str) -> &mut Proc {
        crate::process::labelled(&mut self.procs, label)
    }

    /// The client configuration `{name}.json5`, made local.
    pub fn cfg(&self, name: &str) -> PathBuf {
        local_config(self.dir(), &format!("{name}.json5"), self.port)
    }

    /// Every process's log.
    pub fn logs(&self) -> String {
        crate::process::logs(&self.procs)
    }

    /// Every message the router's access control refused (started with
    /// [`Secure::start_auditing`]): who was refused what on which key, once
    /// each.
    ///
    /// When the router first meets a key it decides every kind of message
    /// on it ahead, for its cache (`caching permissions for …`), and logs
    /// those decisions too; they are not refusals of a message sent and are
    /// left out. A message's own decision is logged from the cache (`Using
    /// cached result: {session} is unauthorized to …`) or, for a key not
    /// cached, directly (`{session} on {subject} is unauthorized to …`).
    pub fn denials(&self) -> Vec<String> {
        use std::collections::{BTreeSet, HashMap};
        let log = std::fs::read_to_string(&self.procs[0].log).unwrap_or_default();
        // Per (flow, key) being cached: how many of its ahead decisions
        // (one per kind of message) are still to come.
        let mut ahead: HashMap<(String, String), usize> = HashMap::new();
        let mut subject: HashMap<String, String> = HashMap::new();
        let mut found = BTreeSet::new();
        for line in log.lines() {
            let Some(at) = line.find(&format!("{ACL_LOG}: ")) else {
                continue;
            };
            let msg = &line[at + ACL_LOG.len() + 2..];
            if let Some(rest) = msg.strip_prefix("ACL (") {
                // `ACL (ingress): caching permissions for `KEY` ...`
                let flow = rest.split(')').next().unwrap_or_default();
                if let Some(key) = rest.split('`').nth(1) {
                    ahead.insert((flow.to_string(), key.to_string()), CACHED_KINDS);
                }
                continue;
            }
            let (from_cache, msg) = match msg.strip_prefix("Using cached result: ") {
                Some(m) => (true, m),
                None => (false, msg),
            };
            let verdict = [" is unauthorized to ", " is authorized to "]
                .into_iter()
                .find_map(|v| msg.find(v).map(|i| (i, v)));
            let Some((i, verdict)) = verdict else {
                continue;
            };
            let (session, rest) = (&msg[..i], &msg[i + verdict.len()..]);
            let session = match session.split_once(" on ") {
                Some((zid, who)) => {
                    subject.insert(zid.to_string(), who.to_string());
                    zid
                }
                None => session,
            };
            let Some((action, key)) = rest.rsplit_once(" on ") else {
                continue;
            };
            let flow = action
                .rsplit('(')
                .next()
                .unwrap_or_default()
                .trim_end_matches(')');
            let for_cache = !from_cache
                && match ahead.get_mut(&(flow.to_string(), key.to_string())) {
                    Some(left) if *left > 0 => {
                        *left -= 1;
                        true
                    }
                    _ => false,
                };
            if verdict == " is unauthorized to " && !for_cache {
                let who = subject.get(session).map_or(session, String::as_str);
                found.insert(format!("{who}: {action} on {key}"));
            }
        }
        found.into_iter().collect()
    }

    /// The processes that no longer run, each with how it ended (the last
    /// lines of its log).
    pub fn dead(&mut self) -> Vec<String> {
        let mut dead = Vec::new();
        for p in &mut self.procs {
            if !p.running() {
                let log = std::fs::read_to_string(&p.log).unwrap_or_default();
                let tail: Vec<&str> = log.lines().rev().take(5).collect();
                dead.push(format!("{}: {}", p.name, tail.join(" | ")));
            }
        }
        dead
    }
}

/// Runs the real `gearcam ARGS --json --config CONFIG` with the extra
/// environment `env`: its exit code and the JSON it printed (its standard
/// error as a JSON string when it printed none).
pub fn gearcam_json(
    config: &Path,
    args: &[&str],
    env: &[(&str, &str)],
) -> (Option<i32>, serde_json::Value) {
    let out = Command::new(crate::bin("gearcam"))
        .args(args)
        .args(["--json", "--config", &config.display().to_string()])
        .envs(env.iter().copied())
        .stdin(std::process::Stdio::null())
        .output()
        .expect("gearcam runs");
    let v = serde_json::from_slice(&out.stdout).unwrap_or_else(|_| {
        serde_json::Value::String(String::from_utf8_lossy(&out.stderr).into_owned())
    });
    (out.status.code(), v)
}

fn strings(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| (*s).to_string()).collect()
}
