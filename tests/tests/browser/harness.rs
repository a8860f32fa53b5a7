//! A shop for the browser tests: every service as its own process behind a
//! router on loopback, agents of H01, M01 and W02, the page (`gearcam web`)
//! with the users of [`gearcam_testkit::web_users`], and a headless Chromium
//! driven over WebDriver (`chromedriver`, Debian's `chromium-driver`).

use std::os::unix::process::CommandExt;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use tokio::time::Instant;

use fantoccini::{Client, ClientBuilder, Locator};
use gearcam_testkit::{start_web, web_password, Cluster, Proc};

/// One browser test at a time: each starts its own services and browser,
/// and two at once on a small machine would only slow both.
static ONE_AT_A_TIME: tokio::sync::Mutex<()> = tokio::sync::Mutex::const_new(());

/// Waits for the other browser tests to end; hold the guard for the test.
pub(crate) async fn one_at_a_time() -> tokio::sync::MutexGuard<'static, ()> {
    ONE_AT_A_TIME.lock().await
}

/// The services, the page and its address.
pub(crate) struct Shop {
    /// The services (they stop when the shop is dropped).
    #[allow(dead_code)]
    pub(crate) cluster: Cluster,
    /// The page's server (stops when dropped).
    #[allow(dead_code)]
    pub(crate) web: Proc,
    /// The page's address, e.g. `http://127.0.0.1:40123`.
    pub(crate) base: String,
}

impl Shop {
    /// Starts the services, the agents of `machines` and the page.
    pub(crate) fn start(machines: &[&str]) -> Shop {
        let mut cluster = Cluster::start_without_agent();
        for m in machines {
            cluster.start_agent_for(m);
        }
        let (web, addr) = start_web(&cluster);
        let base = format!("http://{addr}");
        Shop { cluster, web, base }
    }

    /// The page's address of `path`.
    pub(crate) fn url(&self, path: &str) -> String {
        format!("{}{path}", self.base)
    }
}

/// A headless Chromium and its WebDriver.
pub(crate) struct Browser {
    driver: Child,
    /// The WebDriver session.
    pub(crate) client: Client,
}

/// Where the tests save their screenshots.
pub(crate) fn screenshots() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("screenshots");
    std::fs::create_dir_all(&dir).expect("the screenshots' directory");
    dir
}

impl Browser {
    /// Starts `chromedriver` on a free port and a headless Chromium through it.
    pub(crate) async fn start() -> Browser {
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("a free port")
            .port();
        // Its own process group, so that the browser it starts ends with it
        // even when a failing test never closes the session.
        let driver = Command::new(chromedriver())
            .process_group(0)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts (Debian: apt-get install chromium chromium-driver)");
        let mut caps = serde_json::Map::new();
        caps.insert(
            "goog:chromeOptions".into(),
            serde_json::json!({
                "args": ["--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1280,1000"],
            }),
        );
        let deadline = Instant::now() + Duration::from_secs(30);
        let client = loop {
            let connector = hyper_util::client::legacy::connect::HttpConnector::new();
            match ClientBuilder::new(connector)
                .capabilities(caps.clone())
                .connect(&format!("http://127.0.0.1:{port}"))
                .await
            {
                Ok(c) => break c,
                Err(e) if Instant::now() < deadline => {
                    let _ = e;
                    tokio::time::sleep(Duration::from_millis(200)).await;
                }
                Err(e) => panic!("no WebDriver session on chromedriver: {e}"),
            }
        };
        Browser { driver, client }
    }

    /// Signs in as `name` (a user of [`gearcam_testkit::web_users`]).
    pub(crate) async fn sign_in(&self, shop: &Shop, name: &str) {
        let c = &self.client;
        c.goto(&shop.url("/signin"))
            .await
            .expect("the sign-in page");
        c.find(Locator::Css("input[name=name]"))
            .await
            .unwrap()
            .send_keys(name)
            .await
            .unwrap();
        c.find(Locator::Css("input[name=password]"))
            .await
            .unwrap()
            .send_keys(&web_password(name))
            .await
            .unwrap();
        c.find(Locator::Id("signin"))
            .await
            .unwrap()
            .click()
            .await
            .unwrap();
        self.wait_for_text("nav .who", name).await;
    }

    /// Waits up to 30 s for an element matching `css` whose text contains `text`.
    pub(crate) async fn wait_for_text(&self, css: &str, text: &str) -> String {
        let deadline = Instant::now() + Duration::from_secs(30);
        loop {
            if let Ok(elements) = self.client.find_all(Locator::Css(css)).await {
                for e in elements {
                    if let Ok(t) = e.text().await {
                        if t.contains(text) {
                            return t;
                        }
                    }
                }
            }
            if Instant::now() > deadline {
                let source = self.client.source().await.unwrap_or_default();
                panic!("no {css} with {text:?} within 30 s; the page:\n{source}");
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    }

    /// Saves a screenshot of the page as `name.png` in [`screenshots`].
    pub(crate) async fn screenshot(&self, name: &str) -> PathBuf {
        let png = self.client.screenshot().await.expect("a screenshot");
        let path = screenshots().join(format!("{name}.png"));
        std::fs::write(&path, png).expect("the screenshot saved");
        path
    }

    /// Ends the browser session and the driver.
    pub(crate) async fn stop(self) {
        let _ = self.client.clone().close().await;
        // Dropping it ends the driver and the browser.
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        // The driver's process group: the driver and the browser it started.
        let _ = Command::new("kill")
            .args(["-s", "KILL", "--", &format!("-{}", self.driver.id())])
            .status();
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}

/// The `chromedriver` binary on the `PATH` (Debian's `chromium-driver`).
fn chromedriver() -> PathBuf {
    PathBuf::from("chromedriver")
}
