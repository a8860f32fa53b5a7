//! `gearcam demo`: the main job on an embedded default: start what `up` starts on a
//! loopback session, submit the bundled examples, show the programs and the
//! typed refusals, stop.

use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::Context;
use gearcam_bus::BusArgs;

use crate::bus_config;
use crate::check;
use crate::cmd::check::template_library;
use crate::cmd::progress;
use crate::embedded::Embedded;
use crate::examples::{expected_code, INVALID, VALID};
use crate::jobfile;
use crate::station::{self, Outcome, SubmitOptions};

pub async fn demo(data: &Path, web: std::net::SocketAddr, serve: bool) -> anyhow::Result<ExitCode> {
    let data = &match crate::data_dir::open(data) {
        Ok(data) => data,
        Err(code) => return Ok(code),
    };
    let config = bus_config::embedded(&BusArgs::default(), "tcp/127.0.0.1:0");
    let services = Embedded::start(&config, data, template_library(data)?).await?;
    crate::outln!(
        "gearcam demo: services up on a loopback session; data in {}",
        data.display()
    );
    let stop = tokio_util::sync::CancellationToken::new();
    let page = crate::cmd::web::beside(&services, data, web, stop.clone()).await?;
    // The page's address line comes from its task: let it print first.
    tokio::time::sleep(Duration::from_millis(50)).await;
    crate::outln!();
    let opts = SubmitOptions {
        wait: true,
        alive_timeout: Duration::from_secs(10),
        timeout: Duration::from_secs(30),
    };
    let mut all_ok = true;
    for (origin, text) in VALID {
        let spec = jobfile::parse(text, origin).map_err(|e| anyhow::anyhow!("{e}"))?;
        let req = jobfile::request(spec);
        crate::outln!("── {origin}: job {}", req.job_id);
        let pb = progress(false);
        let outcome = station::submit(&services.bus, &req, &opts, |ev| {
            pb.suspend(|| crate::outln!("   {}", station::describe(ev)));
        })
        .await?;
        pb.finish_and_clear();
        match outcome {
            Outcome::Delivered(r, _) => {
                crate::outln!(
                    "   delivered to {} as {} (sha256 {})\n",
                    r.machine,
                    r.path,
                    r.sha256
                );
                let text = std::fs::read_to_string(&r.path)
                    .with_context(|| format!("reading back {}", r.path))?;
                crate::outln!("{text}");
            }
            other => {
                all_ok = false;
                crate::outln!("   NOT delivered: {other:?}\n");
            }
        }
    }
    for (origin, text) in INVALID {
        let code = expected_code(text).unwrap_or("an error");
        let spec = match jobfile::parse(text, origin) {
            Ok(spec) => spec,
            Err(e) => {
                crate::out!(
                    "── {origin}: refused at the station\n{}",
                    check::format_errors(&[e])
                );
                continue;
            }
        };
        let req = jobfile::request(spec);
        crate::outln!(
            "── {origin}: job {} (invalid on purpose: expect {code})",
            req.job_id
        );
        match station::submit(&services.bus, &req, &opts, |_| {}).await? {
            Outcome::Failed(errors) => {
                crate::out!("{}", check::format_errors(&errors));
                if !errors.iter().any(|e| e.code == code) {
                    all_ok = false;
                    crate::outln!("   expected the refusal to name {code}");
                }
            }
            other => {
                all_ok = false;
                crate::outln!("   expected a refusal, got {other:?}");
            }
        }
    }
    if serve {
        crate::outln!("\ngearcam demo: the services and the web page keep running (Ctrl-C stops)");
        gearcam_bus::cancel_on_signal().cancelled().await;
    }
    stop.cancel();
    if let Ok(Err(e)) = page.await {
        crate::outln!("gearcam demo: the web page stopped: {e:#}");
    }
    services.stop().await;
    crate::outln!(
        "\ngearcam demo: {}",
        if all_ok {
            "every example delivered, every invalid one refused with its named error"
        } else {
            "FAILED"
        }
    );
    Ok(if all_ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
