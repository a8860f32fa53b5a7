//! A machine's program store in the page: two jobs of the same part make
//! two versions of one program; an operator of H01 compares them, rolls
//! back through the confirmation page (the agent's file is the old text
//! again), meets an edit made at the machine as a conflict and adopts it;
//! a planner reads but is refused every change; bad addresses are named.

use std::path::PathBuf;
use std::time::Duration;

use fantoccini::Locator;
use gearcam_testkit::examples::example;
use tokio::time::Instant;

use super::harness::{self, Browser, Shop};

/// The hobbing example `spur_840d.toml` under the job id `id`.
fn job_text(id: &str) -> String {
    let text = example("spur_840d.toml");
    let with_id = text.replacen("# id = \"SP-1001-A\"", &format!("id = \"{id}\""), 1);
    assert_ne!(with_id, text, "the example has the commented id line");
    with_id
}

/// `fetch(url)` in the page (same origin, the session's cookie), with a
/// form carrying the page's CSRF token for a `POST`: the status, the
/// `Content-Disposition` header and the body.
async fn fetch(b: &Browser, method: &str, url: &str) -> (u64, String, String) {
    let script = r#"
        const [method, url, done] = arguments;
        const token = document.querySelector('input[name=csrf]');
        const init = { method };
        if (method === 'POST') {
            init.headers = { 'Content-Type': 'application/x-www-form-urlencoded' };
            init.body = 'csrf=' + encodeURIComponent(token ? token.value : '');
        }
        fetch(url, init).then(r => r.text().then(t =>
            done([r.status, r.headers.get('content-disposition') || '', t])));
    "#;
    let v = b
        .client
        .execute_async(script, vec![method.into(), url.into()])
        .await
        .expect("the fetch in the page");
    (
        v[0].as_u64().expect("a status"),
        v[1].as_str().unwrap_or_default().to_string(),
        v[2].as_str().unwrap_or_default().to_string(),
    )
}

/// Opens `url` again and again (up to 60 s) until an element matching
/// `css` contains `text`: for what the page learns only from the bus.
async fn reload_until(b: &Browser, url: &str, css: &str, text: &str) -> String {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        b.client.goto(url).await.unwrap();
        if let Ok(elements) = b.client.find_all(Locator::Css(css)).await {
            for e in elements {
                if let Ok(t) = e.text().await {
                    if t.contains(text) {
                        return t;
                    }
                }
            }
        }
        if Instant::now() > deadline {
            let source = b.client.source().await.unwrap_or_default();
            panic!("no {css} with {text:?} within 60 s at {url}; the page:\n{source}");
        }
        tokio::time::sleep(Duration::from_millis(500)).await;
    }
}

/// Clicks the element matching `css`.
async fn click(b: &Browser, css: &str) {
    b.client
        .find(Locator::Css(css))
        .await
        .unwrap_or_else(|e| panic!("no {css}: {e}"))
        .click()
        .await
        .unwrap();
}

/// The version numbers of the program page's history, newest first.
async fn seqs(b: &Browser) -> Vec<u64> {
    let mut out = Vec::new();
    for row in b
        .client
        .find_all(Locator::Css("#versions tbody tr"))
        .await
        .unwrap()
    {
        let seq = row.attr("data-seq").await.unwrap().expect("data-seq");
        out.push(seq.parse().unwrap());
    }
    out
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_operator_compares_rolls_back_and_adopts_and_a_planner_only_reads() {
    let _one = harness::one_at_a_time().await;
    let shop = Shop::start(&["H01"]);
    let cluster = &shop.cluster;
    let (_, first) = cluster.submit_wait(&cluster.job_file("a.toml", &job_text("SP-1001-A")));
    assert_eq!(first["state"], "delivered", "{first}");
    let name = first["program"]["name"].as_str().unwrap().to_string();
    let file = PathBuf::from(first["program"]["path"].as_str().unwrap());
    let v1_text = std::fs::read_to_string(&file).unwrap();
    let (_, second) = cluster.submit_wait(&cluster.job_file("b.toml", &job_text("SP-1001-B")));
    assert_eq!(second["state"], "delivered", "{second}");
    assert_eq!(
        second["program"]["name"],
        name.as_str(),
        "one program, two versions"
    );
    assert_ne!(std::fs::read_to_string(&file).unwrap(), v1_text);

    let b = Browser::start().await;
    b.sign_in(&shop, "operator").await;
    // From the navigation to the machine, its programs and the program.
    click(&b, "nav a[href='/machines']").await;
    b.wait_for_text("#machines", "H01").await;
    click(&b, "#machines a").await;
    b.wait_for_text("#programs", &name).await;
    click(&b, "#programs td a").await;
    b.wait_for_text("h1", &format!("Program {name} at H01"))
        .await;
    let program = b.client.current_url().await.unwrap().to_string();
    let current = b
        .wait_for_text("tr.current", "delivered by job SP-1001-B")
        .await;
    assert!(
        current.contains("cylindrical_840d"),
        "the header's template: {current}"
    );
    let [v2, v1] = seqs(&b).await[..] else {
        panic!("two versions")
    };

    // The diff of the two versions: the job line changed.
    click(&b, &format!("tr[data-seq='{v2}'] a.diff")).await;
    b.wait_for_text("h1", &format!("version {v1} → version {v2}"))
        .await;
    b.wait_for_text("#diff tr.del", "SP-1001-A").await;
    b.wait_for_text("#diff tr.add", "SP-1001-B").await;
    b.screenshot("program-diff").await;

    // Roll back to version 1 through its confirmation page.
    b.client.goto(&program).await.unwrap();
    click(&b, &format!("tr[data-seq='{v1}'] a.rollback")).await;
    b.wait_for_text("h1", &format!("to version {v1}?")).await;
    let replaced = b.wait_for_text("#replace", "replaced").await;
    assert!(
        replaced.contains("SP-1001-B") && replaced.contains("SP-1001-A"),
        "{replaced}"
    );
    assert_ne!(
        std::fs::read_to_string(&file).unwrap(),
        v1_text,
        "nothing changed before the POST"
    );
    click(&b, "#confirm").await;
    b.wait_for_text(
        "tr.current",
        &format!("rolled back to version {v1} by operator"),
    )
    .await;
    assert_eq!(
        std::fs::read_to_string(&file).unwrap(),
        v1_text,
        "the agent's file is version 1 again"
    );
    let (status, disposition, text) =
        fetch(&b, "GET", &format!("{program}/versions/{v1}/download")).await;
    assert_eq!(status, 200);
    assert_eq!(disposition, "attachment; filename=\"_N_SP_1001_MPF\"");
    assert_eq!(text, v1_text);

    // An operator of H01 changes nothing of H02.
    let (status, _, page) = fetch(
        &b,
        "GET",
        &shop.url(&format!(
            "/machines/H02/programs/{name}/versions/{v1}/rollback"
        )),
    )
    .await;
    assert_eq!(status, 403, "{page}");
    assert!(
        page.contains("an operator of H01 may not change the programs of machine H02"),
        "{page}"
    );

    // An edit at the machine meets the next delivery: a conflict to review.
    let edited = v1_text.replacen("; PART SP-1001", "; PART SP-1001 EDITED AT THE MACHINE", 1);
    assert_ne!(edited, v1_text);
    std::fs::write(&file, &edited).unwrap();
    cluster.submit(&cluster.job_file("c.toml", &job_text("SP-1001-C")));
    let conflict = reload_until(&b, &program, "#conflict", "SP-1001-C").await;
    assert!(
        conflict.contains("PROGRAM_CHANGED_AT_MACHINE"),
        "{conflict}"
    );
    b.screenshot("program-conflict").await;
    click(&b, "#adopt").await;
    let adopted = b.wait_for_text("tr.current", "adopted by operator").await;
    assert!(
        b.client.find(Locator::Id("conflict")).await.is_err(),
        "resolved"
    );
    assert_eq!(
        std::fs::read_to_string(&file).unwrap(),
        edited,
        "the edit stays"
    );
    let _ = adopted;
    let adopted_seq = seqs(&b).await[0];
    click(&b, &format!("tr[data-seq='{adopted_seq}'] a.diff")).await;
    b.wait_for_text("#diff tr.add", "EDITED AT THE MACHINE")
        .await;
    cluster.wait_status("SP-1001-C", |v| v["state"] == "superseded");

    // A planner reads, and is refused every change.
    click(&b, "#signout").await;
    b.sign_in(&shop, "planner").await;
    b.client.goto(&program).await.unwrap();
    b.wait_for_text("tr.current", "adopted by operator").await;
    let buttons = b
        .client
        .find_all(Locator::Css("a.rollback, #adopt, #replace"))
        .await
        .unwrap();
    assert!(buttons.is_empty(), "a planner sees no change");
    b.screenshot("program-store").await;
    let refusal = "a planner may not change the programs of machine H01";
    let rollback = format!("{program}/versions/{v1}/rollback");
    let (status, _, page) = fetch(&b, "POST", &rollback).await;
    assert_eq!(status, 403, "{page}");
    assert!(page.contains(refusal), "{page}");
    b.client.goto(&rollback).await.unwrap();
    b.wait_for_text(".refused", refusal).await;
    b.client.goto(&program).await.unwrap();
    b.wait_for_text("tr.current", "adopted by operator").await;
    assert_eq!(
        std::fs::read_to_string(&file).unwrap(),
        edited,
        "the planner changed nothing"
    );

    // Bad addresses name the field, what it takes and what was given, as text.
    for (path, status, field, given) in [
        (
            "/machines/H01/programs/..%2Fx".to_string(),
            400,
            "name",
            "../x",
        ),
        (
            "/machines/H01/programs/%3Cb%3Ebold".to_string(),
            400,
            "name",
            "<b>bold",
        ),
        (
            format!("/machines/H01/programs/{name}/versions/abc"),
            400,
            "seq",
            "abc",
        ),
        (
            format!("/machines/H01/programs/{name}/diff?a=1&b=x"),
            400,
            "b",
            "x",
        ),
        ("/machines/H09".to_string(), 404, "machine", "H09"),
    ] {
        let (got, _, page) = fetch(&b, "GET", &shop.url(&path)).await;
        assert_eq!(got, status, "{path}: {page}");
        b.client.goto(&shop.url(&path)).await.unwrap();
        let row = b.wait_for_text("table.errors tbody tr", given).await;
        assert!(row.starts_with(field), "{path}: {row}");
        assert!(
            b.client.find(Locator::Css("table.errors b")).await.is_err(),
            "{path}: markup ran"
        );
    }
    let machine = b.wait_for_text("table.errors", "H09").await;
    assert!(
        machine.contains("a machine whose agent is on the bus: H01"),
        "{machine}"
    );
    b.stop().await;
}
