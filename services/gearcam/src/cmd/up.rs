//! `gearcam up`: every service and one agent per machine in this process.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;
use gearcam_bus::{cancel_on_signal, BusArgs};

use crate::bus_config;
use crate::cmd::check::template_library;
use crate::embedded::Embedded;
use crate::DEFAULT_ENDPOINT;

pub async fn up(data: &Path, web: std::net::SocketAddr, bus: &BusArgs) -> anyhow::Result<ExitCode> {
    let data = &match crate::data_dir::open(data) {
        Ok(data) => data,
        Err(code) => return Ok(code),
    };
    let config = bus_config::embedded(bus, DEFAULT_ENDPOINT);
    let mut services = Embedded::start(&config, data, template_library(data)?)
        .await
        .with_context(|| format!("starting the services (listening on {:?})", config.listen))?;
    crate::outln!(
        "gearcam up: all services running; listening on {}",
        config.listen.join(", ")
    );
    crate::outln!("  knowledge base {}", data.join("knowledge.db").display());
    for m in &services.machines {
        crate::outln!(
            "  agent {} ({}, {}) stores programs in {}",
            m.id,
            m.name,
            m.dialect.as_str(),
            m.dir.display()
        );
    }
    let stop = cancel_on_signal();
    let page = crate::cmd::web::beside(&services, data, web, stop.clone()).await?;
    crate::outln!("submit with: gearcam submit examples/spur_840d.toml --wait   (Ctrl-C stops)");
    let result = services.serve_until(stop).await;
    if let Ok(Err(e)) = page.await {
        tracing::warn!("the web page stopped: {e:#}");
    }
    services.stop().await;
    result.map(|()| ExitCode::SUCCESS)
}
