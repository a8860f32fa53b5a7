//! The services alive on the bus as a liveliness subscriber sees them, so
//! that a stage asks its memory, not the network, before each message.
//!
//! The subscriber takes the tokens already declared (history) and follows
//! every token declared or dropped after. A name it has not seen is not
//! proof of absence (the history may still be on its way): a caller asks the
//! bus then ([`crate::Bus::is_alive`]).

use std::collections::HashSet;
use std::sync::{Arc, Mutex};

use gearcam_proto::keys;
use tokio_util::sync::CancellationToken;
use zenoh::sample::SampleKind;

use crate::{zerr, Bus, BusError};

/// The liveliness tokens seen, by service name.
#[derive(Debug, Clone, Default)]
pub struct Alive {
    names: Arc<Mutex<HashSet<String>>>,
}

impl Alive {
    /// Follows the liveliness tokens `gearcam/v1/alive/**` until `shutdown`.
    pub async fn follow(bus: &Bus, shutdown: CancellationToken) -> Result<Alive, BusError> {
        let sub = bus
            .session()
            .liveliness()
            .declare_subscriber(keys::ALIVE_ANY)
            .history(true)
            .await
            .map_err(zerr("liveliness subscriber"))?;
        let alive = Alive::default();
        let names = alive.names.clone();
        tokio::spawn(async move {
            loop {
                let s = tokio::select! {
                    _ = shutdown.cancelled() => break,
                    s = sub.recv_async() => match s { Ok(s) => s, Err(_) => break },
                };
                let Some(name) = keys::alive_of(s.key_expr().as_str()) else {
                    continue;
                };
                let Ok(mut names) = names.lock() else { break };
                if s.kind() == SampleKind::Put {
                    names.insert(name.to_string());
                } else {
                    names.remove(name);
                }
            }
        });
        Ok(alive)
    }

    /// True when `service`'s token has been seen and not dropped since.
    pub fn seen(&self, service: &str) -> bool {
        self.names.lock().is_ok_and(|n| n.contains(service))
    }

    /// True when `service` is alive: from memory when its token has been
    /// seen, otherwise by asking the bus.
    pub async fn check(&self, bus: &Bus, service: &str) -> Result<bool, BusError> {
        if self.seen(service) {
            return Ok(true);
        }
        bus.is_alive(service).await
    }
}
