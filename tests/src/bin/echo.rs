//! `gearcam-echo`: the far end of the raw Zenoh request/reply measurement in
//! the pipeline benchmark (`tests/benches/pipeline.rs`).
//!
//! It opens a client session to a router, answers every query on
//! `bench/echo/{size}` with a reply of `{size}` bytes (the query's own payload
//! is read and dropped), and declares the liveliness token `bench/alive/echo`
//! once the queryable is in place. It does no other work, so what the
//! benchmark measures against it is Zenoh's own cost for one request/reply
//! between two processes through the router.
//!
//! ```sh
//! gearcam-echo --connect tcp/127.0.0.1:7447
//! ```
// Test code: clocks for timeouts, the environment for switches.
#![allow(clippy::disallowed_methods)]

use anyhow::{bail, Context, Result};

/// Key expression the echo queryable serves.
const ECHO_KEYS: &str = "bench/echo/*";
/// Liveliness token declared once the queryable serves.
const ALIVE: &str = "bench/alive/echo";

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let mut connect = None;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--connect" => connect = Some(args.next().context("--connect needs an endpoint")?),
            other => bail!("unknown argument {other:?}; usage: gearcam-echo --connect ENDPOINT"),
        }
    }
    let connect = connect.context("usage: gearcam-echo --connect ENDPOINT")?;
    tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the tokio runtime")?
        .block_on(serve(&connect))
}

async fn serve(connect: &str) -> Result<()> {
    let mut config = zenoh::Config::default();
    let setting = |e: zenoh::Error| anyhow::anyhow!("invalid Zenoh setting: {e}");
    config.insert_json5("mode", "\"client\"").map_err(setting)?;
    config
        .insert_json5("connect/endpoints", &format!("[\"{connect}\"]"))
        .map_err(setting)?;
    config
        .insert_json5("scouting/multicast/enabled", "false")
        .map_err(setting)?;
    let session = zenoh::open(config)
        .await
        .map_err(|e| anyhow::anyhow!("cannot open a Zenoh session to {connect}: {e}"))?;
    let queryable = session
        .declare_queryable(ECHO_KEYS)
        .await
        .map_err(|e| anyhow::anyhow!("cannot declare the queryable {ECHO_KEYS}: {e}"))?;
    let _alive = session
        .liveliness()
        .declare_token(ALIVE)
        .await
        .map_err(|e| anyhow::anyhow!("cannot declare the liveliness token {ALIVE}: {e}"))?;
    while let Ok(query) = queryable.recv_async().await {
        let size = query
            .key_expr()
            .as_str()
            .rsplit('/')
            .next()
            .and_then(|s| s.parse::<usize>().ok());
        let sent = match size {
            Some(size) => {
                // Touch the request payload as a real service would.
                let _request = query.payload().map(|p| p.to_bytes());
                query
                    .reply(query.key_expr().clone(), vec![0x5a; size])
                    .await
            }
            None => {
                query
                    .reply_err(format!(
                        "expected bench/echo/{{size}}, got {}",
                        query.key_expr()
                    ))
                    .await
            }
        };
        if let Err(e) = sent {
            eprintln!("gearcam-echo: cannot reply: {e}");
        }
    }
    Ok(())
}
