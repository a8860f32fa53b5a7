//! A job's picture and program on its page: a hobbing job's set-up and
//! path, a spiral face and a wire die, each drawn from the model the station
//! journaled and zoomed with the page's control; the hobbing job's program
//! as the machine's agent stored it.

use std::time::Duration;

use fantoccini::Locator;
use serde_json::{json, Value};
use tokio::time::Instant;

use super::harness::{self, Browser, Shop};

/// Submits an example and waits for its delivery; the `gearcam submit`
/// JSON (job id, program, receipt).
fn delivered(shop: &Shop, example: &str) -> Value {
    let text = gearcam_testkit::examples::example(example);
    let path = shop.cluster.job_file(example, &text);
    let (out, v) = shop.cluster.submit_wait(&path);
    assert_eq!(
        v["state"],
        "delivered",
        "{example}: {v}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    v
}

/// Runs `script` in the page until it returns something other than
/// `null`, `false` or `0`, for up to 30 s; what it returned.
async fn wait_for_js(b: &Browser, script: &str) -> Value {
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        let v = b.client.execute(script, vec![]).await.unwrap();
        if !matches!(&v, Value::Null | Value::Bool(false)) && v.as_f64().is_none_or(|n| n != 0.0) {
            return v;
        }
        if Instant::now() > deadline {
            let source = b.client.source().await.unwrap_or_default();
            panic!("{script} stayed {v} for 30 s; the page:\n{source}");
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

/// The picture's transform as the page has it now.
async fn transform(b: &Browser) -> String {
    let v = b
        .client
        .execute(
            "return document.querySelector('.zoomable img').style.transform",
            vec![],
        )
        .await
        .unwrap();
    v.as_str().unwrap_or_default().to_string()
}

/// Opens the job's page and sees its picture: loaded (a natural width),
/// fetched by the page as an SVG with `marks` in it and no script; zooms in
/// with the control and sees the picture's transform change; saves the
/// screenshot `shot`.
async fn sees_picture(b: &Browser, shop: &Shop, job: &str, marks: &[&str], shot: &str) {
    b.client
        .goto(&shop.url(&format!("/jobs/{job}")))
        .await
        .unwrap();
    b.wait_for_text("h1", &format!("Job {job}")).await;
    let width = wait_for_js(
        b,
        "const i = document.querySelector('.zoomable img'); return i && i.complete ? i.naturalWidth : 0",
    )
    .await;
    assert!(width.as_f64().unwrap() > 100.0, "{job}: {width}");
    let fetched = b
        .client
        .execute_async(
            "const done = arguments[arguments.length - 1];
             fetch(arguments[0]).then(r => r.text().then(t =>
                 done({status: r.status, type: r.headers.get('content-type'),
                       csp: r.headers.get('content-security-policy'), text: t})));",
            vec![json!(format!("/jobs/{job}/picture.svg"))],
        )
        .await
        .unwrap();
    assert_eq!(fetched["status"], 200, "{job}");
    assert_eq!(fetched["type"], "image/svg+xml", "{job}");
    assert!(
        fetched["csp"]
            .as_str()
            .unwrap()
            .contains("default-src 'none'"),
        "{job}"
    );
    let svg = fetched["text"].as_str().unwrap();
    assert!(
        svg.starts_with("<svg"),
        "{job}: {}",
        &svg[..80.min(svg.len())]
    );
    assert!(!svg.contains("<script"), "{job}");
    for mark in marks {
        assert!(svg.contains(mark), "{job}: no {mark:?} in the picture");
    }
    let before = transform(b).await;
    b.client
        .find(Locator::Css(".zoom-tools .zoom-in"))
        .await
        .unwrap()
        .click()
        .await
        .unwrap();
    let after = transform(b).await;
    assert_ne!(before, after, "{job}: the zoom changed nothing");
    assert!(after.contains("scale(1.25)"), "{job}: {after}");
    b.screenshot(shot).await;
    b.client
        .find(Locator::Css(".zoom-tools .zoom-reset"))
        .await
        .unwrap()
        .click()
        .await
        .unwrap();
    assert_eq!(transform(b).await, before, "{job}: reset");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_planner_sees_each_jobs_picture_zooms_it_and_reads_its_program() {
    let _one = harness::one_at_a_time().await;
    let shop = Shop::start(&["H01", "M01", "W02"]);
    let hobbing = delivered(&shop, "spur_840d.toml");
    let face = delivered(&shop, "face_annulus_fanuc.toml");
    let die = delivered(&shop, "die_m1z40_iso.toml");
    let job = |v: &Value| v["job"].as_str().unwrap().to_string();
    let b = Browser::start().await;
    b.sign_in(&shop, "planner").await;

    // The hobbing job's set-up: its positions, the hob, the blank.
    sees_picture(
        &b,
        &shop,
        &job(&hobbing),
        &["C X73.75 Z154.278", "hob Ø80 × 100", "blank: tip Ø81"],
        "picture-hobbing",
    )
    .await;
    // The gear the hobbing job's program cuts on the virtual machine: its
    // measuring charts, drawn when the planner opens them.
    b.client
        .find(Locator::Css("details#simulation summary"))
        .await
        .unwrap()
        .click()
        .await
        .unwrap();
    let width = wait_for_js(
        &b,
        "const i = document.querySelector('#simulation img'); return i && i.complete ? i.naturalWidth : 0",
    )
    .await;
    assert!(width.as_f64().unwrap() > 100.0, "charts: {width}");
    b.screenshot("simulation-charts").await;
    // The spiral face: its radii and the coverage found.
    sees_picture(
        &b,
        &shop,
        &job(&face),
        &["Ro 100 mm, Ri 20 mm", "covered"],
        "picture-spiral",
    )
    .await;
    // The die: its part, module and teeth.
    sees_picture(&b, &shop, &job(&die), &["die m1 z40"], "picture-die").await;

    // The hobbing job's program from its page: the text the agent stored,
    // header to end, and its download.
    let id = job(&hobbing);
    b.client
        .goto(&shop.url(&format!("/jobs/{id}")))
        .await
        .unwrap();
    b.client
        .find(Locator::Css("#program-links a"))
        .await
        .unwrap()
        .click()
        .await
        .unwrap();
    b.wait_for_text("pre#program", "GEARCAM HOBBING PROGRAM")
        .await;
    let shown = b
        .client
        .execute(
            "return document.getElementById('program').textContent",
            vec![],
        )
        .await
        .unwrap();
    let stored = std::fs::read_to_string(hobbing["program"]["path"].as_str().unwrap()).unwrap();
    assert_eq!(shown.as_str().unwrap(), stored, "the program as stored");
    assert!(stored.contains(&format!("; JOB {id}")), "{stored}");
    assert!(stored.contains("END OF PROGRAM"), "{stored}");
    b.screenshot("program").await;
    let download = b
        .client
        .execute_async(
            "const done = arguments[arguments.length - 1];
             const a = document.getElementById('download');
             fetch(a.href).then(r => r.text().then(t =>
                 done({disposition: r.headers.get('content-disposition'), text: t})));",
            vec![],
        )
        .await
        .unwrap();
    assert_eq!(download["text"].as_str().unwrap(), stored);
    assert_eq!(
        download["disposition"],
        "attachment; filename=\"_N_SP_1001_MPF\""
    );
    b.stop().await;
}
