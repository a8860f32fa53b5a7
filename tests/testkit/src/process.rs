//! The real binaries as processes on loopback, each in a fresh temporary
//! directory, stopped when the test ends.
//!
//! - [`bin`]: the path of a built workspace binary.
//! - [`Proc`]: one process, its log, and what it printed.
//! - [`Cluster`]: a router plus every service and one agent, as processes.
//!
//! Ports come from the operating system: a router listens on port 0 and the
//! port it got is read back from what it prints (`gearcam router: listening
//! on …`); a restarted router takes the same port again.

use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The path of a workspace binary built next to the test executable
/// (`target/<profile>/<name>`), or in `$GEARCAM_BIN_DIR` when set.
/// `cargo test --workspace` builds them: every package with a binary has an
/// integration test, which makes cargo build that binary.
pub fn bin(name: &str) -> PathBuf {
    let dir = match std::env::var_os("GEARCAM_BIN_DIR") {
        Some(d) => PathBuf::from(d),
        None => {
            let exe = std::env::current_exe().expect("test executable path");
            exe.parent()
                .and_then(|deps| deps.parent())
                .expect("target/<profile>/deps/<test>")
                .to_path_buf()
        }
    };
    let path = dir.join(name);
    assert!(
        path.exists(),
        "{} is missing: run the tests with `cargo test --workspace` (it builds every service binary), or `cargo build --workspace --bins` first",
        path.display()
    );
    path
}

/// Waits until something accepts TCP connections on the port.
///
/// A loopback connect to a port of the ephemeral range can connect to itself
/// (TCP simultaneous open, when the kernel picks the same port as the source):
/// such a connection proves nothing listens and is not counted. (It let the
/// services start before their router in a CI run, and they exited.)
pub fn wait_for_port(port: u16, timeout: Duration) {
    let start = Instant::now();
    loop {
        match TcpStream::connect(("127.0.0.1", port)) {
            Ok(s) if s.local_addr().map(|a| a.port()).ok() != Some(port) => return,
            _ => {}
        }
        assert!(
            start.elapsed() < timeout,
            "nothing listens on port {port} after {timeout:?}"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Runs the built `gearcam` binary with `args` (stdin closed); its exit
/// code, standard output and standard error.
pub fn gearcam(args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(bin("gearcam"))
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("gearcam runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Writes a users file of the web page in `dir` with `gearcam web-user`:
/// `planner`, `operator` (of H01), `admin` and `supervisor`, each with the
/// password [`web_password`] of their name. Returns the file's path.
pub fn web_users(dir: &Path) -> PathBuf {
    let path = dir.join("web-users.toml");
    for (name, role, machine) in [
        ("planner", "planner", None),
        ("operator", "operator", Some("H01")),
        ("admin", "admin", None),
        ("supervisor", "supervisor", None),
    ] {
        let mut args = vec![
            "web-user".to_string(),
            name.to_string(),
            "--role".into(),
            role.into(),
            "--users".into(),
            path.display().to_string(),
        ];
        if let Some(m) = machine {
            args.extend(["--machine".to_string(), m.to_string()]);
        }
        let mut child = Command::new(bin("gearcam"))
            .args(&args)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .spawn()
            .expect("gearcam web-user runs");
        use std::io::Write;
        writeln!(child.stdin.take().expect("stdin"), "{}", web_password(name)).unwrap();
        let status = child.wait().expect("gearcam web-user ends");
        assert!(status.success(), "gearcam web-user {name}: {status}");
    }
    path
}

/// Starts `gearcam web` for `cluster` on a free loopback port, with the
/// users of [`web_users`] and the cluster's directory as its data
/// directory (the knowledge base its form checks against); the process and
/// its address (`127.0.0.1:PORT`).
pub fn start_web(cluster: &Cluster) -> (Proc, String) {
    let users = web_users(cluster.dir());
    let web = Proc::start(
        cluster.dir(),
        "web",
        "gearcam",
        &[
            "web",
            "--listen",
            "127.0.0.1:0",
            "--users",
            &users.display().to_string(),
            "--data",
            &cluster.dir().display().to_string(),
            "--connect",
            &cluster.endpoint,
        ]
        .map(String::from),
    );
    // The line's text after the prefix: `127.0.0.1:PORT/`.
    let line = web.wait_for_line("gearcam web: http://", Duration::from_secs(30));
    let addr = line.trim_end_matches('/').to_string();
    (web, addr)
}

/// The password [`web_users`] gives the user `name`.
pub fn web_password(name: &str) -> String {
    format!("{name}-secret-1")
}

/// A child process killed when dropped; its stderr goes to a log file.
#[derive(Debug)]
pub struct Proc {
    /// Name for messages.
    pub name: String,
    child: Child,
    /// Log file with the process's stderr.
    pub log: PathBuf,
    bin: String,
    args: Vec<String>,
    rust_log: String,
}

impl Proc {
    /// Starts `bin(name)` with `args`, logging to `dir/name.log`.
    pub fn start(dir: &Path, label: &str, name: &str, args: &[String]) -> Proc {
        Proc::start_logging(dir, label, name, args, "info")
    }

    /// [`Proc::start`] with the log filter `rust_log` (`RUST_LOG`).
    pub fn start_logging(
        dir: &Path,
        label: &str,
        name: &str,
        args: &[String],
        rust_log: &str,
    ) -> Proc {
        let log = dir.join(format!("{label}.log"));
        let child = spawn(&log, name, args, rust_log);
        Proc {
            name: label.to_string(),
            child,
            log,
            bin: name.to_string(),
            args: args.to_vec(),
            rust_log: rust_log.to_string(),
        }
    }

    /// Starts the process again with the same arguments (after a kill).
    pub fn restart(&mut self) {
        self.kill();
        self.child = spawn(&self.log, &self.bin, &self.args, &self.rust_log);
    }

    /// Waits until the process has printed a line starting with `prefix`;
    /// returns the rest of that line.
    pub fn wait_for_line(&self, prefix: &str, timeout: Duration) -> String {
        let start = Instant::now();
        loop {
            let log = std::fs::read_to_string(&self.log).unwrap_or_default();
            if let Some(rest) = log.lines().find_map(|l| l.strip_prefix(prefix)) {
                return rest.trim().to_string();
            }
            assert!(
                start.elapsed() < timeout,
                "{} printed no line {prefix:?} within {timeout:?}:\n{log}",
                self.name
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// The port this process listens on, read back from the operating
    /// system (`/proc`: the process's TCP sockets in the LISTEN state, else
    /// its bound UDP socket for QUIC) once it listens. Start a router with port 0 and ask here which it got.
    pub fn listening_port(&self, timeout: Duration) -> u16 {
        let start = Instant::now();
        loop {
            if let Some(port) = listening_port(self.child.id()) {
                return port;
            }
            assert!(
                start.elapsed() < timeout,
                "{} listens on no port after {timeout:?}:\n{}",
                self.name,
                std::fs::read_to_string(&self.log).unwrap_or_default()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// The endpoint of a router started by this process with `--listen
    /// tcp/127.0.0.1:0`: the port the operating system chose. From then on a
    /// restart listens there again.
    pub fn router_endpoint(&mut self, timeout: Duration) -> String {
        let port = self.listening_port(timeout);
        let endpoint = format!("tcp/127.0.0.1:{port}");
        for a in &mut self.args {
            if a == "tcp/127.0.0.1:0" {
                a.clone_from(&endpoint);
            }
        }
        endpoint
    }

    /// The process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// True while the process runs.
    pub fn running(&mut self) -> bool {
        matches!(self.child.try_wait(), Ok(None))
    }

    /// Kills the process (SIGKILL) and waits for it.
    pub fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Proc {
    fn drop(&mut self) {
        self.kill();
    }
}

/// The port process `pid` listens on (Linux `/proc`): a TCP port it
/// listens on, else the UDP port it is bound to (a QUIC listener), if any.
pub fn listening_port(pid: u32) -> Option<u16> {
    let inodes: Vec<String> = std::fs::read_dir(format!("/proc/{pid}/fd"))
        .ok()?
        .filter_map(|e| std::fs::read_link(e.ok()?.path()).ok())
        .filter_map(|l| {
            let l = l.to_string_lossy().into_owned();
            Some(l.strip_prefix("socket:[")?.strip_suffix(']')?.to_string())
        })
        .collect();
    // A TCP socket in the LISTEN state (0A), else (QUIC) a bound UDP socket (07).
    [
        ("/proc/net/tcp", "0A"),
        ("/proc/net/tcp6", "0A"),
        ("/proc/net/udp", "07"),
        ("/proc/net/udp6", "07"),
    ]
    .iter()
    .find_map(|(table, listening)| {
        let text = std::fs::read_to_string(table).ok()?;
        text.lines().skip(1).find_map(|line| {
            let f: Vec<&str> = line.split_whitespace().collect();
            // local_address, st, inode
            let (local, state, inode) = (f.get(1)?, f.get(3)?, f.get(9)?);
            if state != listening || !inodes.iter().any(|i| i == inode) {
                return None;
            }
            u16::from_str_radix(local.rsplit(':').next()?, 16).ok()
        })
    })
}

fn spawn(log: &Path, name: &str, args: &[String], rust_log: &str) -> Child {
    let file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(log)
        .expect("log file");
    let mut cmd = Command::new(bin(name));
    // Run in the test's directory, so a default relative path (the services'
    // `gearcam-data/`) lands there and never in the checkout.
    if let Some(dir) = log.parent() {
        cmd.current_dir(dir);
    }
    cmd.args(args)
        .env("RUST_LOG", rust_log)
        .stdin(Stdio::null())
        .stdout(file.try_clone().expect("log file"))
        .stderr(file)
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {name}: {e}"))
}

/// A router and every service as separate processes on loopback.
#[derive(Debug)]
pub struct Cluster {
    /// Temporary directory holding data and logs.
    pub dir: tempfile::TempDir,
    /// The router's endpoint, e.g. `tcp/127.0.0.1:40123`.
    pub endpoint: String,
    /// The processes.
    pub procs: Vec<Proc>,
}

impl Cluster {
    /// Starts a router, the planning station, the knowledge, model and
    /// template services and the agent of machine H01, each a separate
    /// process, as clients of the router.
    pub fn start() -> Cluster {
        Cluster::start_simulating("fine")
    }

    /// [`Cluster::start`] with the template service's `--simulation` mode
    /// (`fine`, its default, `coarse` or `off`).
    pub fn start_simulating(simulation: &str) -> Cluster {
        let mut c = Cluster::start_without_agent_simulating(simulation);
        c.start_agent();
        c
    }

    /// Like [`Cluster::start`] but the agent of H01 is not started (offline).
    pub fn start_without_agent() -> Cluster {
        Cluster::start_without_agent_simulating("fine")
    }

    fn start_without_agent_simulating(simulation: &str) -> Cluster {
        let dir = tempfile::tempdir().expect("temp dir");
        let d = dir.path();
        let mut router = Proc::start(
            d,
            "router",
            "gearcam",
            &[
                "router".into(),
                "--listen".into(),
                "tcp/127.0.0.1:0".into(),
                "--no-multicast-scouting".into(),
            ],
        );
        let endpoint = router.router_endpoint(Duration::from_secs(20));
        let client = |extra: &[&str]| -> Vec<String> {
            let mut v: Vec<String> = [
                "--mode",
                "client",
                "--connect",
                &endpoint,
                "--no-multicast-scouting",
            ]
            .iter()
            .map(|s| s.to_string())
            .collect();
            v.extend(extra.iter().map(|s| s.to_string()));
            v
        };
        let mut procs = vec![router];
        let journal = d.join("station.db").display().to_string();
        procs.push(Proc::start(
            d,
            "station",
            "gearcam",
            &client(&["--journal", &journal, "--redrive-ms", "1000"])
                .into_iter()
                .fold(vec!["station".to_string()], |mut v, a| {
                    v.push(a);
                    v
                }),
        ));
        let db = d.join("knowledge.db").display().to_string();
        procs.push(Proc::start(
            d,
            "knowledge",
            "gearcam-knowledge",
            &client(&["--db", &db]),
        ));
        procs.push(Proc::start(d, "model", "gearcam-model", &client(&[])));
        let library = d.join("templates.db").display().to_string();
        procs.push(Proc::start(
            d,
            "template",
            "gearcam-template",
            &client(&["--library", &library, "--simulation", simulation]),
        ));
        Cluster {
            dir,
            endpoint,
            procs,
        }
    }

    /// Starts the agent of machine H01 (a separate process).
    pub fn start_agent(&mut self) {
        self.start_agent_for("H01");
    }

    /// Starts the agent of `machine` (a separate process, labelled `agent`
    /// for H01 and `agent-{machine}` otherwise), its store under `{machine}/`;
    /// H02 (hobbing) and M01 (milling) are the seeded FANUC machines, M02
    /// the LinuxCNC mill, W01 the 3B/4B and W02 the ISO wire EDM machine,
    /// every other an 840D.
    pub fn start_agent_for(&mut self, machine: &str) {
        let label = if machine == "H01" {
            "agent".to_string()
        } else {
            format!("agent-{machine}")
        };
        self.start_agent_with(&label, machine, &[]);
    }

    /// Starts an agent of `machine` labelled `label`, with `extra` arguments
    /// (e.g. a fault to inject), on the same store as [`Cluster::start_agent_for`].
    pub fn start_agent_with(&mut self, label: &str, machine: &str, extra: &[&str]) {
        let d = self.dir.path();
        let programs = d.join(machine).join("programs").display().to_string();
        let index = d.join(machine).join("index.db").display().to_string();
        let mut args: Vec<String> = [
            "--mode",
            "client",
            "--connect",
            &self.endpoint,
            "--no-multicast-scouting",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        args.extend(
            [
                "--machine",
                machine,
                "--dialect",
                match machine {
                    "H02" | "M01" => "fanuc",
                    "M02" => "linuxcnc",
                    "W01" => "wire3b",
                    "W02" => "wireiso",
                    _ => "sinumerik840d",
                },
                "--program-dir",
                &programs,
                "--index",
                &index,
            ]
            .iter()
            .map(|s| s.to_string()),
        );
        args.extend(extra.iter().map(|s| s.to_string()));
        let agent = Proc::start(d, label, "gearcam-agent", &args);
        self.procs.push(agent);
    }

    /// The cluster's directory (each agent's store is under `{machine}/`).
    pub fn dir(&self) -> &Path {
        self.dir.path()
    }

    /// The agent's program directory.
    pub fn program_dir(&self) -> PathBuf {
        self.dir.path().join("H01/programs")
    }

    /// The agent's index database.
    pub fn index_db(&self) -> PathBuf {
        self.dir.path().join("H01/index.db")
    }

    /// Writes a job file into the cluster's directory.
    pub fn job_file(&self, name: &str, text: &str) -> PathBuf {
        let path = self.dir.path().join(name);
        std::fs::write(&path, text).expect("job file");
        path
    }

    /// Runs `gearcam submit FILE --connect <router> --wait --json`.
    pub fn submit_wait(&self, job: &Path) -> (Output, serde_json::Value) {
        let out = Command::new(bin("gearcam"))
            .args([
                "submit",
                &job.display().to_string(),
                "--connect",
                &self.endpoint,
                "--wait",
                "--json",
                "--timeout",
                "60",
            ])
            .stdin(Stdio::null())
            .output()
            .expect("gearcam submit runs");
        let stdout = String::from_utf8_lossy(&out.stdout);
        let value = serde_json::from_str(stdout.trim()).unwrap_or_else(|e| {
            panic!(
                "submit printed no JSON ({e}): stdout {stdout:?} stderr {:?}\n{}",
                String::from_utf8_lossy(&out.stderr),
                self.logs()
            )
        });
        (out, value)
    }

    /// The process with this label (`router`, `station`, `knowledge`, `model`, `template`, `agent`).
    pub fn proc(&mut self, label: &str) -> &mut Proc {
        labelled(&mut self.procs, label)
    }

    /// Runs `gearcam submit FILE --connect <router> --json` (returns once journaled).
    pub fn submit(&self, job: &Path) -> serde_json::Value {
        let out = Command::new(bin("gearcam"))
            .args([
                "submit",
                &job.display().to_string(),
                "--connect",
                &self.endpoint,
                "--json",
                "--timeout",
                "60",
            ])
            .stdin(Stdio::null())
            .output()
            .expect("gearcam submit runs");
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "submit failed: {stdout} {}\n{}",
            String::from_utf8_lossy(&out.stderr),
            self.logs()
        );
        serde_json::from_str(stdout.trim())
            .unwrap_or_else(|e| panic!("submit printed no JSON ({e}): {stdout:?}"))
    }

    /// `gearcam jobs --json` through the router: every journaled job.
    pub fn jobs(&self) -> Option<Vec<serde_json::Value>> {
        let out = Command::new(bin("gearcam"))
            .args(["jobs", "--connect", &self.endpoint, "--json"])
            .stdin(Stdio::null())
            .output()
            .expect("gearcam jobs runs");
        if !out.status.success() {
            return None;
        }
        serde_json::from_slice::<Vec<serde_json::Value>>(&out.stdout).ok()
    }

    /// Waits until `gearcam status JOB --json` satisfies `done` (60 s at
    /// most); returns that status.
    pub fn wait_status(
        &self,
        id: &str,
        done: impl Fn(&serde_json::Value) -> bool,
    ) -> serde_json::Value {
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            let (_, out, _) = gearcam(&["status", id, "--connect", &self.endpoint, "--json"]);
            if let Ok(v) = serde_json::from_str::<serde_json::Value>(&out) {
                if done(&v) {
                    return v;
                }
                assert!(
                    Instant::now() < deadline,
                    "job {id} stuck: {v}\n{}",
                    self.logs()
                );
            }
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    /// Waits until the station reports `n` jobs, all delivered; returns them.
    pub fn wait_all_delivered(&self, n: usize, timeout: Duration) -> Vec<serde_json::Value> {
        let start = Instant::now();
        let mut last = None;
        while start.elapsed() < timeout {
            if let Some(jobs) = self.jobs() {
                if jobs.len() == n && jobs.iter().all(|j| j["state"] == "delivered") {
                    return jobs;
                }
                last = Some(jobs);
            }
            std::thread::sleep(Duration::from_millis(300));
        }
        let states: Vec<String> = last
            .unwrap_or_default()
            .iter()
            .map(|j| format!("{} {} {}", j["job"], j["state"], j["waiting_for"]))
            .collect();
        panic!(
            "not all {n} jobs delivered after {timeout:?}: {states:#?}\n{}",
            self.logs()
        );
    }

    /// Every process's log, for failure messages.
    pub fn logs(&self) -> String {
        logs(&self.procs)
    }

    /// Asserts every process still runs.
    pub fn assert_all_running(&mut self) {
        let mut dead = Vec::new();
        for p in &mut self.procs {
            if !p.running() {
                dead.push(p.name.clone());
            }
        }
        assert!(dead.is_empty(), "processes died: {dead:?}\n{}", self.logs());
    }
}

/// The configuration of a plain Zenoh client session to `endpoint` (a test's
/// own client, as a foreign program would connect): client mode, that
/// endpoint only, no multicast scouting.
pub fn client_config(endpoint: &str) -> zenoh::Config {
    let mut config = zenoh::Config::default();
    config
        .insert_json5("mode", "\"client\"")
        .expect("mode is a setting");
    config
        .insert_json5("connect/endpoints", &format!("[\"{endpoint}\"]"))
        .expect("connect/endpoints is a setting");
    config
        .insert_json5("scouting/multicast/enabled", "false")
        .expect("scouting/multicast/enabled is a setting");
    config
}

/// Every process's log, each under its label, for failure messages.
pub fn logs(procs: &[Proc]) -> String {
    procs
        .iter()
        .map(|p| {
            format!(
                "--- {} ---\n{}",
                p.name,
                std::fs::read_to_string(&p.log).unwrap_or_default()
            )
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The process labelled `label` of `procs`.
pub fn labelled<'a>(procs: &'a mut [Proc], label: &str) -> &'a mut Proc {
    procs
        .iter_mut()
        .find(|p| p.name == label)
        .unwrap_or_else(|| panic!("no process {label}"))
}
