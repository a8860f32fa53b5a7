//! The knowledge base in the page: an admin's edit of a hob refused with
//! the knowledge service's errors beside the fields they name, then made
//! and seen in the change log as the admin's; a material added and removed
//! after a page that asks; a planner who sees no edit control and whose
//! direct POST of the edit form is refused naming the role; a planner who
//! confirms a delivered job and sees it become a case.

use fantoccini::Locator;
use gearcam_testkit::examples;

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

/// Clicks the element with the id `id`.
async fn click(b: &Browser, id: &str) {
    b.client
        .find(Locator::Id(id))
        .await
        .unwrap_or_else(|e| panic!("no #{id}: {e}"))
        .click()
        .await
        .unwrap();
}

/// The inline errors beside the form's field `name`, once they name `code`.
async fn field_error(b: &Browser, name: &str, code: &str) -> String {
    b.wait_for_text(&format!("p.field[data-field='{name}'] .field-error"), code)
        .await
}

/// POSTs `body` (with the page's CSRF token) to `path` from the page, as
/// a script of the signed-in user could; the status and the page's text.
async fn post_from_page(b: &Browser, path: &str, body: &str) -> (u64, String) {
    let script = r#"
        const [path, body, done] = arguments;
        const csrf = document.querySelector("input[name=csrf]").value;
        fetch(path, {
            method: "POST",
            headers: {"Content-Type": "application/x-www-form-urlencoded"},
            body: "csrf=" + encodeURIComponent(csrf) + "&" + body,
        }).then(r => r.text().then(t => done([r.status, t])));
    "#;
    let v = b
        .client
        .execute_async(script, vec![path.into(), body.into()])
        .await
        .expect("the script runs");
    (
        v[0].as_u64().expect("a status"),
        v[1].as_str().expect("a page").to_string(),
    )
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_admin_edits_the_knowledge_base_and_a_planner_confirms_a_job() {
    let _one = harness::one_at_a_time().await;
    let shop = Shop::start(&["H01"]);
    // A delivered job, for the planner to confirm.
    let file = shop
        .cluster
        .job_file("spur.toml", &examples::example("spur_840d.toml"));
    let (_, v) = shop.cluster.submit_wait(&file);
    assert_eq!(v["state"], "delivered", "{v}");
    let job = v["job"].as_str().expect("a job id").to_string();
    let b = Browser::start().await;
    b.sign_in(&shop, "admin").await;

    // The libraries with their fields, units in the labels.
    b.client.goto(&shop.url("/kb")).await.unwrap();
    b.wait_for_text("#lib-hobs", "module_mm (mm)").await;
    b.wait_for_text("#lib-machines", "machine profile").await;
    b.client.goto(&shop.url("/kb/hobs")).await.unwrap();
    b.wait_for_text("#records", "HOB-M3-80").await;

    // A negative module and a text in a number field: the knowledge
    // service's errors beside the fields, naming what it takes and what it got.
    b.client
        .goto(&shop.url("/kb/hobs/HOB-M3-80/edit"))
        .await
        .unwrap();
    b.wait_for_text("p.field[data-field='od_mm'] label", "od_mm (mm)")
        .await;
    type_into(&b, "module_mm", "-3").await;
    type_into(&b, "od_mm", "eighty").await;
    click(&b, "save").await;
    let module = field_error(&b, "module_mm", "FIELD_INVALID").await;
    assert!(module.contains("expected a number > 0, got -3"), "{module}");
    let od = field_error(&b, "od_mm", "FIELD_INVALID").await;
    assert!(od.contains("got \"eighty\""), "{od}");
    b.wait_for_text("#summary", "nothing was changed").await;
    b.screenshot("kb-edit").await;

    // A machine's nested field, by its dotted path with the unit its name
    // says: a text where a number goes is refused beside it.
    b.client
        .goto(&shop.url("/kb/machines/H01/edit"))
        .await
        .unwrap();
    b.wait_for_text(
        "p.field[data-field='limits.max_hob_rpm'] label",
        "limits.max_hob_rpm (rpm)",
    )
    .await;
    type_into(&b, "limits.max_hob_rpm", "fast").await;
    click(&b, "save").await;
    let rpm = field_error(&b, "limits.max_hob_rpm", "FIELD_INVALID").await;
    assert!(rpm.contains("fast"), "{rpm}");
    b.screenshot("kb-edit-machine").await;

    // A valid edit: the record after it, then the change log has it as the admin's.
    b.client
        .goto(&shop.url("/kb/hobs/HOB-M3-80/edit"))
        .await
        .unwrap();
    type_into(&b, "coating", "AlCrN").await;
    click(&b, "save").await;
    b.wait_for_text("#done", "Changed by admin").await;
    b.wait_for_text("td[data-field='coating']", "AlCrN").await;
    b.wait_for_text("td[data-field='module_mm']", "3").await;
    b.client.goto(&shop.url("/kb/changes")).await.unwrap();
    let row = b
        .wait_for_text("#changes tr.change[data-record='HOB-M3-80']", "AlCrN")
        .await;
    assert!(row.contains("admin") && row.contains("edit"), "{row}");
    assert!(row.contains("coating") && row.contains("→ AlCrN"), "{row}");
    b.screenshot("kb-changes").await;

    // A material added, then removed after the page that asks.
    b.client.goto(&shop.url("/kb/new/materials")).await.unwrap();
    type_into(&b, "name", "TEST-STEEL").await;
    type_into(&b, "material_group", "test_group").await;
    type_into(&b, "hardness_hb", "210").await;
    click(&b, "save").await;
    b.wait_for_text("#done", "Added by admin").await;
    click(&b, "remove").await;
    b.wait_for_text("h1", "Remove materials TEST-STEEL?").await;
    click(&b, "confirm-remove").await;
    b.wait_for_text("#done", "Removed by admin").await;
    b.client.goto(&shop.url("/kb/materials")).await.unwrap();
    let table = b.wait_for_text("#records", "40Cr").await;
    assert!(!table.contains("TEST-STEEL"), "{table}");

    // A planner: no edit control, and a direct POST of the edit form is
    // refused naming the role; the hob is as the admin left it.
    b.sign_in(&shop, "planner").await;
    b.client
        .goto(&shop.url("/kb/hobs/HOB-M3-80"))
        .await
        .unwrap();
    b.wait_for_text("td[data-field='coating']", "AlCrN").await;
    for control in ["edit", "copy", "remove"] {
        assert!(
            b.client.find(Locator::Id(control)).await.is_err(),
            "a planner sees #{control}"
        );
    }
    let (status, text) = post_from_page(&b, "/kb/hobs/HOB-M3-80/edit", "coating=TiN").await;
    assert_eq!(status, 403, "{text}");
    assert!(text.contains("signed in as planner"), "{text}");
    b.client.refresh().await.unwrap();
    b.wait_for_text("td[data-field='coating']", "AlCrN").await;

    // The planner confirms the delivered job from its page: a confidence
    // out of range is refused beside its field, then the job becomes a case.
    b.client
        .goto(&shop.url(&format!("/jobs/{job}")))
        .await
        .unwrap();
    click(&b, "confirm-link").await;
    b.wait_for_text("#job-state", "delivered").await;
    let speed = b
        .client
        .find(Locator::Css("input[name='cutting_speed_m_min']"))
        .await
        .unwrap()
        .prop("value")
        .await
        .unwrap()
        .unwrap_or_default();
    assert!(
        speed.parse::<f64>().is_ok(),
        "the plan's speed proposed: {speed:?}"
    );
    type_into(&b, "confidence", "2").await;
    click(&b, "confirm").await;
    let error = field_error(&b, "confidence", "FIELD_INVALID").await;
    assert!(error.contains("got 2"), "{error}");
    type_into(&b, "confidence", "0.9").await;
    click(&b, "confirm").await;
    let case = format!("JOB-{job}");
    b.wait_for_text("#done", &case).await;
    b.screenshot("kb-confirm").await;
    b.client.goto(&shop.url("/kb/cases")).await.unwrap();
    b.wait_for_text("#records", &case).await;
    b.client
        .goto(&shop.url(&format!("/kb/cases/{case}")))
        .await
        .unwrap();
    b.wait_for_text("td[data-field='provenance']", "by planner")
        .await;
    b.stop().await;
}
