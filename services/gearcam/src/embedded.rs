//! The embedded default: every service and one agent per configured machine in
//! this process, on one Zenoh session (`gearcam up`, `gearcam demo`).

use std::path::{Path, PathBuf};
use std::time::Duration;

use gearcam_agent::store::StoreConfig;
use gearcam_bus::{Bus, BusConfig, CancellationToken};
use gearcam_proto::{keys, Dialect, MachineId};
use gearcam_template::Templates;
use tokio::task::JoinSet;

/// Where the embedded services keep their data under the data directory.
#[derive(Debug, Clone)]
pub struct DataLayout {
    /// The data directory.
    pub root: PathBuf,
}

impl DataLayout {
    /// The knowledge base file.
    pub fn knowledge_db(&self) -> PathBuf {
        self.root.join("knowledge.db")
    }

    /// The planning station's job journal.
    pub fn journal(&self) -> PathBuf {
        self.root.join("station.db")
    }

    /// A machine's program directory.
    pub fn program_dir(&self, machine: &MachineId) -> PathBuf {
        self.root
            .join("machines")
            .join(machine.as_str())
            .join("programs")
    }

    /// A machine's program index.
    pub fn index_db(&self, machine: &MachineId) -> PathBuf {
        self.root
            .join("machines")
            .join(machine.as_str())
            .join("index.db")
    }
}

/// A machine an embedded agent serves.
#[derive(Debug, Clone)]
pub struct Served {
    /// Machine id.
    pub id: MachineId,
    /// Human name.
    pub name: String,
    /// Controller dialect (the store's naming).
    pub dialect: Dialect,
    /// Its program directory.
    pub dir: PathBuf,
}

/// Running embedded services.
#[derive(Debug)]
pub struct Embedded {
    /// The shared session.
    pub bus: Bus,
    /// Machines served (hobbing, milling and wire EDM), with their program directories.
    pub machines: Vec<Served>,
    shutdown: CancellationToken,
    tasks: JoinSet<(&'static str, anyhow::Result<()>)>,
}

impl Embedded {
    /// Opens the session and starts every service; returns once all are
    /// alive. The template service runs every hobbing program on the
    /// virtual machine before it is delivered
    /// ([`gearcam_template::simulation::before_delivery`]).
    pub async fn start(
        bus_config: &BusConfig,
        data: &Path,
        templates: Templates,
    ) -> anyhow::Result<Embedded> {
        let layout = DataLayout {
            root: data.to_path_buf(),
        };
        // Create and seed the knowledge base before the services start, so the
        // agents know which machines exist.
        let machines: Vec<(MachineId, String, Dialect)> = {
            let conn = gearcam_knowledge::db::open(&layout.knowledge_db())?;
            let hobbing = gearcam_knowledge::db::machines(&conn)?
                .into_iter()
                .map(|m| (m.id, m.name, m.dialect));
            let milling = gearcam_knowledge::spiral::mill_machines(&conn)?
                .into_iter()
                .map(|m| (m.id, m.name, m.dialect));
            let wire = gearcam_knowledge::wire::wire_machines(&conn)?
                .into_iter()
                .map(|m| (m.id, m.name, m.dialect));
            hobbing.chain(milling).chain(wire).collect()
        };
        let bus = Bus::open(bus_config).await?;
        let shutdown = CancellationToken::new();
        let mut tasks = JoinSet::new();
        let (b, s) = (bus.clone(), shutdown.clone());
        let cfg = gearcam_knowledge::service::Config {
            db_path: layout.knowledge_db(),
        };
        tasks.spawn(async move {
            (
                "knowledge",
                gearcam_knowledge::service::run(b, cfg, s)
                    .await
                    .map_err(Into::into),
            )
        });
        let (b, s) = (bus.clone(), shutdown.clone());
        tasks.spawn(async move {
            (
                "model",
                gearcam_model::service::run(b, s).await.map_err(Into::into),
            )
        });
        let (b, s) = (bus.clone(), shutdown.clone());
        let templates =
            templates.with_simulation(Some(gearcam_template::simulation::before_delivery()));
        tasks.spawn(async move {
            (
                "template",
                gearcam_template::service::run(b, templates, s)
                    .await
                    .map_err(Into::into),
            )
        });
        let (b, s) = (bus.clone(), shutdown.clone());
        let station = gearcam_station::StationConfig {
            journal: layout.journal(),
            redrive: Duration::from_secs(5),
        };
        tasks.spawn(async move {
            (
                "station",
                gearcam_station::run(b, station, s)
                    .await
                    .map_err(Into::into),
            )
        });
        let mut served = Vec::new();
        let mut services = vec![
            gearcam_proto::keys::STATION_SERVICE.to_string(),
            gearcam_knowledge::service::SERVICE.to_string(),
            gearcam_model::service::SERVICE.to_string(),
            gearcam_template::service::SERVICE.to_string(),
        ];
        for (id, name, dialect) in machines {
            let cfg = StoreConfig {
                machine: id.clone(),
                dialect,
                program_dir: layout.program_dir(&id),
                index_path: layout.index_db(&id),
                faults: Default::default(),
            };
            served.push(Served {
                id: id.clone(),
                name,
                dialect,
                dir: cfg.program_dir.clone(),
            });
            services.push(keys::agent_service(&id));
            let (b, s) = (bus.clone(), shutdown.clone());
            tasks.spawn(async move {
                (
                    "agent",
                    gearcam_agent::service::run(b, cfg, s)
                        .await
                        .map_err(Into::into),
                )
            });
        }
        let mut me = Embedded {
            bus,
            machines: served,
            shutdown,
            tasks,
        };
        // A service that fails at start (e.g. an unwritable directory) ends its
        // task; report that instead of waiting for its liveliness in vain.
        tokio::select! {
            r = me.bus.wait_alive(&services, Duration::from_secs(20)) => r?,
            Some(done) = me.tasks.join_next() => {
                let (name, result) = done?;
                me.stop().await;
                anyhow::bail!("the {name} service stopped at start: {}", result.err().map(|e| e.to_string()).unwrap_or_else(|| "no error".into()));
            }
        }
        Ok(me)
    }

    /// Waits until a service task ends on its own (an error) or `stop` is wanted.
    pub async fn serve_until(&mut self, stop: CancellationToken) -> anyhow::Result<()> {
        tokio::select! {
            _ = stop.cancelled() => Ok(()),
            Some(done) = self.tasks.join_next() => {
                let (name, result) = done?;
                match result {
                    Ok(()) => anyhow::bail!("the {name} service stopped"),
                    Err(e) => anyhow::bail!("the {name} service failed: {e}"),
                }
            }
        }
    }

    /// Stops every service, waiting up to 5 s for them to finish, and closes the session.
    pub async fn stop(mut self) {
        self.shutdown.cancel();
        let drain = async {
            while let Some(done) = self.tasks.join_next().await {
                if let Ok((name, Err(e))) = done {
                    tracing::warn!(service = name, error = %e, "service ended with an error");
                }
            }
        };
        if tokio::time::timeout(Duration::from_secs(5), drain)
            .await
            .is_err()
        {
            tracing::warn!("services did not stop within 5 s");
        }
        self.bus.close().await;
    }
}
