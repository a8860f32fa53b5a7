//! The planning office's page in a real browser: headless Chromium over
//! WebDriver against every service as its own process. Screenshots of the
//! main pages are saved in the target directory's `tmp/screenshots/`.

#[path = "browser/harness.rs"]
mod harness;
#[path = "browser/jobs.rs"]
mod jobs;
#[path = "browser/kb.rs"]
mod kb;
#[path = "browser/pictures.rs"]
mod pictures;
#[path = "browser/stores.rs"]
mod stores;

use fantoccini::Locator;
use harness::{Browser, Shop};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_user_signs_in_and_sees_the_queue() {
    let _one = harness::one_at_a_time().await;
    let shop = Shop::start(&["H01"]);
    let b = Browser::start().await;
    // Not signed in: every page leads to the sign-in form.
    b.client.goto(&shop.url("/")).await.unwrap();
    b.wait_for_text("h1", "Sign in").await;
    b.screenshot("signin").await;
    b.sign_in(&shop, "planner").await;
    b.wait_for_text("h1", "Jobs").await;
    b.screenshot("jobs-empty").await;
    b.client
        .find(Locator::Id("signout"))
        .await
        .unwrap()
        .click()
        .await
        .unwrap();
    b.wait_for_text("h1", "Sign in").await;
    b.stop().await;
}
