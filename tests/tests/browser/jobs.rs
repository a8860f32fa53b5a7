//! A planner's day in the page: a hobbing job typed into its form with the
//! check beside the fields while typing, submitted and followed live to
//! `delivered`; a spiral face and a wire die job from their forms; a part
//! number with a script in it shown as text.

use fantoccini::Locator;

use super::harness::{self, Browser, Shop};

/// Replaces the text of the form's field `name` with `value`.
async fn type_into(b: &Browser, name: &str, value: &str) {
    let input = b
        .client
        .find(Locator::Css(&format!("[name='{name}']")))
        .await
        .unwrap_or_else(|e| panic!("no field {name}: {e}"));
    input.clear().await.unwrap();
    input.send_keys(value).await.unwrap();
}

/// Submits the form and waits on the job's page until its state is `delivered`.
async fn submit_and_follow(b: &Browser) -> String {
    b.client
        .find(Locator::Id("submit"))
        .await
        .unwrap()
        .click()
        .await
        .unwrap();
    b.wait_for_text("h1", "Job ").await;
    b.wait_for_text("#state", "delivered").await;
    b.client.current_url().await.unwrap().to_string()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_planner_types_checks_submits_and_follows_jobs_of_every_family() {
    let _one = harness::one_at_a_time().await;
    // H01's agent starts only once the hobbing job waits for it, so the
    // page sees the delivery happen.
    let mut shop = Shop::start(&["M01", "W02"]);
    let b = Browser::start().await;
    b.sign_in(&shop, "planner").await;

    // Hobbing: a module the library hob does not fit is refused while typing.
    b.client.goto(&shop.url("/new/hobbing")).await.unwrap();
    b.wait_for_text("#summary", "passes every check").await;
    type_into(&b, "gear.module_mm", "2.5").await;
    let summary = b.wait_for_text("#summary", "BASE_PITCH_MISMATCH").await;
    assert!(summary.contains("hob.module_mm"), "{summary}");
    b.screenshot("job-form-error").await;
    // A text in a number field names the field, what it takes and what it got.
    type_into(&b, "gear.teeth", "twenty").await;
    let error = b
        .wait_for_text(
            "p.field[data-field='gear.teeth'] .field-error",
            "a whole number",
        )
        .await;
    assert!(error.contains("\"twenty\""), "{error}");
    type_into(&b, "gear.teeth", "25").await;
    type_into(&b, "gear.module_mm", "3.0").await;
    // A script in the part number is only text.
    let script = "<script>alert(1)</script>";
    type_into(&b, "job.part_number", script).await;
    b.wait_for_text("#summary", "passes every check").await;
    let proposal = b
        .wait_for_text(
            "p.field[data-field='process.cutting_speed_m_min'] .proposal",
            "proposed",
        )
        .await;
    assert!(proposal.contains("from"), "{proposal}");
    b.client
        .find(Locator::Id("submit"))
        .await
        .unwrap()
        .click()
        .await
        .unwrap();
    b.wait_for_text("#state", "waiting").await;
    let url = b.client.current_url().await.unwrap().to_string();
    shop.cluster.start_agent_for("H01");
    b.wait_for_text("#state", "delivered").await;
    let progress = b.wait_for_text("#progress", "agent H01: stored").await;
    assert_eq!(
        b.client.current_url().await.unwrap().to_string(),
        url,
        "followed on the job's own page"
    );
    b.wait_for_text("dd", "sha256").await;
    assert!(
        progress.contains("template: program"),
        "every stage after the wait, live: {progress}"
    );
    b.screenshot("job-delivered").await;

    // The queue shows the part number as the text typed, and no script ran.
    b.client.goto(&shop.url("/")).await.unwrap();
    let row = b.wait_for_text("#jobs tr", "alert(1)").await;
    assert!(row.contains(script), "the part number as text: {row}");
    assert!(
        b.client.get_alert_text().await.is_err(),
        "a script of a part number ran"
    );

    // Spiral face milling and a wire die from their forms.
    for form in ["spiral-face", "wire-edm"] {
        b.client
            .goto(&shop.url(&format!("/new/{form}")))
            .await
            .unwrap();
        b.wait_for_text("#summary", "passes every check").await;
        let other = submit_and_follow(&b).await;
        assert_ne!(other, url);
    }
    b.client.goto(&shop.url("/")).await.unwrap();
    b.wait_for_text("#jobs", "W02").await;
    b.screenshot("jobs").await;
    b.stop().await;
}
