//! Every key a service uses is granted to it on the secure deployment: a
//! job of every family on every machine, a job for a machine nobody has,
//! the planner's and the operator's reads, with the router logging every
//! decision of its access control; not one refusal is logged. A key missing
//! from `deploy/secure/router.json5` shows here as the refusal of its
//! subject, action and key, even where the pipeline would only wait.

use std::path::Path;

use gearcam_testkit::examples;
use gearcam_testkit::secure::{gearcam_json, Secure};

/// `gearcam ARGS --json --config CONFIG`: exit code and the JSON printed.
fn cli(config: &Path, args: &[&str]) -> (Option<i32>, serde_json::Value) {
    gearcam_json(config, args, &[])
}

#[test]
fn every_key_a_service_uses_is_granted_on_the_secure_deployment() {
    let mut secure = Secure::start_auditing();
    secure.start_agent("M01", "fanuc");
    secure.start_agent("M02", "linuxcnc");
    secure.start_agent("W02", "wireiso");
    let planner = secure.cfg("planner");
    let operator = secure.cfg("operator");
    let job = |name: &str| {
        let path = secure.dir().join(name);
        std::fs::write(&path, examples::example(name)).expect("a job file");
        path.display().to_string()
    };
    for (example, machine) in [
        ("spur_840d.toml", "H01"),
        ("helical_climb_fanuc.toml", "H02"),
        ("face_annulus_fanuc.toml", "M01"),
        ("face_circle_linuxcnc.toml", "M02"),
        ("die_m2z20_3b.toml", "W01"),
        ("die_m1z40_iso.toml", "W02"),
    ] {
        let (code, v) = cli(
            &planner,
            &["submit", &job(example), "--wait", "--timeout", "60"],
        );
        assert_eq!(code, Some(0), "{example}: {v}\n{}", secure.logs());
        assert_eq!(v["state"], "delivered", "{example}: {v}");
        let id = v["job"].as_str().expect("a job id").to_string();
        assert_eq!(cli(&planner, &["status", &id]).0, Some(0), "{example}");
        let (code, history) = cli(&operator, &["program", "history", "--machine", machine]);
        assert_eq!(code, Some(0), "{machine}: {history}");
    }
    // A machine nobody has is refused at once, as on the plain deployment:
    // the station asks every family's machine list.
    let text = examples::example("die_m2z20_3b.toml").replace("\"W01\"", "\"ZZ99\"");
    let unknown = secure.dir().join("unknown.toml");
    std::fs::write(&unknown, text).expect("a job file");
    let (code, v) = cli(
        &planner,
        &[
            "submit",
            &unknown.display().to_string(),
            "--wait",
            "--timeout",
            "20",
        ],
    );
    assert_eq!(cli(&planner, &["jobs"]).0, Some(0));

    // The control: one query the router must refuse, a planner's change of
    // the knowledge base under the admin's name. It shows the router's
    // refusals are read; it must be the only one.
    let control = gearcam_proto::keys::kb_change("admin", "hobs", None);
    let rt = tokio::runtime::Runtime::new().expect("a runtime");
    rt.block_on(async {
        let config = zenoh::Config::from_file(&planner).expect("planner config");
        let session = zenoh::open(config).await.expect("the planner connects");
        let replies = session
            .get(&control)
            .payload(vec![0x80])
            .timeout(std::time::Duration::from_secs(2))
            .await
            .expect("a query");
        assert!(
            replies.recv_async().await.is_err(),
            "the control was answered"
        );
        session.close().await.expect("the session closes");
    });
    let (expected, denials): (Vec<String>, Vec<String>) =
        secure.denials().into_iter().partition(|d| {
            d.contains("Username(planner)") && d.ends_with(&format!("Query (ingress) on {control}"))
        });
    assert_eq!(
        expected.len(),
        1,
        "the control's refusal was not read from the router's log"
    );
    assert!(
        denials.is_empty(),
        "the router refused what the deployment's own services and users do:\n{}",
        denials.join("\n")
    );
    assert_eq!(code, Some(1), "{v}");
    assert_eq!(v["errors"][0]["code"], "UNKNOWN_MACHINE", "{v}");
}

/// The web page's server on the secure deployment, under its own login
/// (`deploy/secure/web.json5`): a planner signed in to the page submits a
/// job and follows it to delivery, reads the queue, the job, its picture,
/// its program and the knowledge base, and the router refuses none of it.
#[test]
fn the_web_pages_own_login_is_granted_what_its_users_do() {
    use gearcam_testkit::web::{csrf_of, http, sign_in};
    let secure = Secure::start_auditing();
    let users = gearcam_testkit::web_users(secure.dir());
    let web = gearcam_testkit::Proc::start(
        secure.dir(),
        "web",
        "gearcam",
        &[
            "web".to_string(),
            "--listen".into(),
            "127.0.0.1:0".into(),
            "--users".into(),
            users.display().to_string(),
            "--data".into(),
            secure.dir().display().to_string(),
            "--config".into(),
            secure.cfg("web").display().to_string(),
        ],
    );
    let line = web.wait_for_line("gearcam web: http://", std::time::Duration::from_secs(30));
    let addr = line.trim_end_matches('/');
    let cookie = sign_in(addr, "planner");
    let with_cookie = format!("Cookie: {cookie}\r\n");
    let (code, _, form) = http(addr, "GET", "/new/hobbing", &with_cookie, "");
    assert_eq!(code, 200, "{form}");
    let fields = format!(
        "csrf={}&action=submit&job.machine=H01&job.part_number=WEB-1&job.quantity=3&gear.module_mm=3.0&gear.teeth=25&gear.face_width_mm=30&gear.material=C45&gear.fixture_height_mm=100&hob.id=HOB-M3-80",
        csrf_of(&form)
    );
    let (code, head, body) = http(
        addr,
        "POST",
        "/new/hobbing",
        &format!("{with_cookie}Content-Type: application/x-www-form-urlencoded\r\n"),
        &fields,
    );
    assert_eq!(code, 303, "{head}\n{body}\n{}", secure.logs());
    let job = head
        .lines()
        .find_map(|l| l.strip_prefix("location: "))
        .expect("the job's page")
        .to_string();
    // Up to a minute, in steps of 200 ms.
    let delivered = (0..300).any(|_| {
        let (code, _, page) = http(addr, "GET", &job, &with_cookie, "");
        assert_eq!(code, 200, "{page}");
        let done = page.contains("\">delivered</dd>");
        if !done {
            std::thread::sleep(std::time::Duration::from_millis(200));
        }
        done
    });
    assert!(
        delivered,
        "not delivered within a minute\n{}",
        secure.logs()
    );
    for path in [
        "/".to_string(),
        format!("{job}/picture.svg"),
        format!("{job}/program"),
        "/kb/hobs".to_string(),
    ] {
        let (code, _, page) = http(addr, "GET", &path, &with_cookie, "");
        assert_eq!(code, 200, "{path}: {page}");
    }
    assert_eq!(secure.denials(), Vec::<String>::new(), "{}", secure.logs());
}
