//! The planning office's page (`gearcam web`) against real service
//! processes on loopback: the journal's jobs listed and filtered, one job's
//! state, errors and program, every value shown as text (a part number
//! with a script in it is escaped), an unknown job a 404.

use std::time::Duration;

use gearcam_testkit::web::{csrf_of, http, sign_in};
use gearcam_testkit::{examples, start_web, Cluster, Proc};

/// The example `file` with its part number replaced by `part`.
fn with_part(file: &str, part: &str) -> String {
    examples::example(file)
        .lines()
        .map(|l| {
            if l.trim_start().starts_with("part_number") {
                format!("part_number = {part:?}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn the_page_lists_the_journal_and_shows_each_job_as_text() {
    let cluster = Cluster::start();
    let script = "<script>alert(1)</script>";
    let good = cluster.job_file("xss.toml", &with_part("spur_840d.toml", script));
    let (_, v) = cluster.submit_wait(&good);
    assert_eq!(v["state"], "delivered", "{v}\n{}", cluster.logs());
    let bad = cluster.job_file("bad.toml", &examples::example("invalid_base_pitch.toml"));
    let (_, v) = cluster.submit_wait(&bad);
    assert_eq!(v["state"], "failed", "{v}");
    let jobs = cluster.jobs().expect("the station lists its jobs");
    let id_of = |part: &str| {
        jobs.iter()
            .find(|j| j["part_number"] == part)
            .and_then(|j| j["job"].as_str())
            .unwrap_or_else(|| panic!("no job of part {part}: {jobs:?}"))
            .to_string()
    };
    let (delivered, failed) = (id_of(script), id_of("BAD-0001"));

    let (_web, addr) = start_web(&cluster);
    let addr = addr.as_str();
    // Without a session every page leads to the sign-in form.
    let (code, head, _) = http(addr, "GET", "/", "", "");
    assert_eq!(code, 303, "{head}");
    assert!(head.contains("location: /signin?next=/"), "{head}");
    let cookie = sign_in(addr, "planner");
    let get = |path: &str| {
        let (code, _, body) = http(addr, "GET", path, &format!("Cookie: {cookie}\r\n"), "");
        (code, body)
    };

    // The list: both jobs, the part number escaped, never a live script.
    let (code, list) = get("/");
    assert_eq!(code, 200, "{list}");
    assert!(
        list.contains(&delivered) && list.contains(&failed),
        "{list}"
    );
    assert!(
        list.contains("&lt;script&gt;alert(1)&lt;/script&gt;"),
        "{list}"
    );
    assert!(!list.contains(script), "a raw script in the page:\n{list}");
    // The count of parts: 20 of the spur example, 1 of the invalid one.
    assert!(list.contains("2 of 2 job(s), 21 part(s)"), "{list}");

    // Filter by state and search by part number.
    let (_, failed_only) = get("/?state=failed");
    assert!(failed_only.contains(&failed) && !failed_only.contains(&delivered));
    assert!(failed_only.contains("1 of 2 job(s)"), "{failed_only}");
    let (_, searched) = get("/?q=bad-0001");
    assert!(searched.contains(&failed) && !searched.contains(&delivered));

    // One job: its state and program; a failed one's typed errors.
    let (code, page) = get(&format!("/jobs/{delivered}"));
    assert_eq!(code, 200, "{page}");
    assert!(
        page.contains("delivered") && page.contains("SCRIPT_ALERT_1_SCRIPT"),
        "{page}"
    );
    assert!(!page.contains(script), "{page}");
    let (code, page) = get(&format!("/jobs/{failed}"));
    assert_eq!(code, 200, "{page}");
    assert!(
        page.contains("BASE_PITCH_MISMATCH") && page.contains("hob.module_mm"),
        "{page}"
    );

    // Submitted again from its page: the same job under a new id, by the
    // signed-in planner, refused again for the same reason.
    let csrf = csrf_of(&page);
    let (code, head, body) = http(
        addr,
        "POST",
        &format!("/jobs/{failed}/resubmit"),
        &format!("Cookie: {cookie}\r\nContent-Type: application/x-www-form-urlencoded\r\n"),
        &format!("csrf={csrf}"),
    );
    assert_eq!(code, 303, "{head}\n{body}");
    let again = head
        .lines()
        .find_map(|l| l.strip_prefix("location: /jobs/"))
        .expect("the new job's page")
        .to_string();
    assert_ne!(again, failed);
    let jobs = cluster.jobs().expect("the station lists its jobs");
    let new = jobs
        .iter()
        .find(|j| j["job"] == again.as_str())
        .expect("journaled");
    assert_eq!(new["part_number"], "BAD-0001");

    // An unknown job, and a path that is no job id.
    let (code, _) = get("/jobs/NO-SUCH-JOB");
    assert_eq!(code, 404);
    let (code, page) = get("/jobs/%3Cb%3E");
    assert_eq!(code, 404);
    assert!(
        page.contains("&lt;b&gt;") && !page.contains("<b>"),
        "{page}"
    );

    // A wrong password is refused; a change without the session's CSRF
    // token, or from another site, is refused and changes nothing.
    let (code, _, body) = http(
        addr,
        "POST",
        "/signin",
        "Content-Type: application/x-www-form-urlencoded\r\n",
        "name=planner&password=guess",
    );
    assert_eq!(code, 401, "{body}");
    // A sign-in from another site is refused; after a sign-in, only a path
    // of this server is followed (a tab, which browsers drop, does not make
    // `/<tab>/host` another host).
    let form = "Content-Type: application/x-www-form-urlencoded\r\n";
    let (code, _, _) = http(
        addr,
        "POST",
        "/signin",
        &format!("{form}Origin: http://evil.example\r\n"),
        &format!(
            "name=planner&password={}",
            gearcam_testkit::web_password("planner")
        ),
    );
    assert_eq!(code, 403);
    let (code, head, _) = http(
        addr,
        "POST",
        "/signin",
        form,
        &format!(
            "name=planner&password={}&next=%2F%09%2Fevil.example",
            gearcam_testkit::web_password("planner")
        ),
    );
    assert_eq!(code, 303, "{head}");
    assert!(head.contains("location: /\r\n"), "{head}");
    let form = "Content-Type: application/x-www-form-urlencoded\r\n";
    let with_cookie = format!("{form}Cookie: {cookie}\r\n");
    let (code, _, body) = http(addr, "POST", "/signout", &with_cookie, "csrf=forged");
    assert_eq!(code, 403, "{body}");
    let foreign = format!("{with_cookie}Origin: http://evil.example\r\n");
    let (code, _, _) = http(addr, "POST", "/signout", &foreign, "");
    assert_eq!(code, 403);
    let (code, _) = get("/");
    assert_eq!(code, 200, "the session outlives the refused changes");
}

#[test]
fn the_demo_prints_the_pages_address_and_the_page_shows_its_jobs_of_every_family() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let demo = Proc::start(
        dir.path(),
        "demo",
        "gearcam",
        &[
            "demo",
            "--serve",
            "--web",
            "127.0.0.1:0",
            "--data",
            &data.display().to_string(),
        ]
        .map(String::from),
    );
    let url = demo.wait_for_line("gearcam web: http://", Duration::from_secs(60));
    let addr = url.trim_end_matches('/');
    demo.wait_for_line(
        "gearcam demo: the services and the web page keep running",
        Duration::from_secs(300),
    );
    // The first users' passwords, written once beside the users file.
    let passwords = std::fs::read_to_string(data.join("web-passwords.txt")).unwrap();
    let password = passwords
        .lines()
        .find_map(|l| l.strip_prefix("planner "))
        .expect("the planner's first password");
    let users = std::fs::read_to_string(data.join("web-users.toml")).unwrap();
    assert!(
        !users.contains(password) && users.contains("$argon2id$"),
        "only the hash in the users file"
    );
    let (code, head, _) = http(
        addr,
        "POST",
        "/signin",
        "Content-Type: application/x-www-form-urlencoded\r\n",
        &format!("name=planner&password={password}"),
    );
    assert_eq!(code, 303, "{head}");
    let cookie = head
        .lines()
        .find_map(|l| l.strip_prefix("set-cookie: "))
        .and_then(|c| c.split(';').next())
        .unwrap()
        .to_string();
    let (code, _, list) = http(
        addr,
        "GET",
        "/?state=delivered",
        &format!("Cookie: {cookie}\r\n"),
        "",
    );
    assert_eq!(code, 200, "{list}");
    // Hobbing on H01 and H02, spiral face milling on M01 and M02, wire EDM on W01 and W02.
    for machine in ["H01", "H02", "M01", "M02", "W01", "W02"] {
        assert!(
            list.contains(&format!("<td>{machine}</td>")),
            "no delivered job on {machine}:\n{list}"
        );
    }
}

/// A `multipart/form-data` body with the CSRF token and one file.
fn multipart(csrf: &str, file: &str) -> (String, String) {
    let b = "gearcamboundary7MA4YWxk";
    let body = format!(
        "--{b}\r\nContent-Disposition: form-data; name=\"csrf\"\r\n\r\n{csrf}\r\n--{b}\r\nContent-Disposition: form-data; name=\"file\"; filename=\"job.toml\"\r\nContent-Type: application/toml\r\n\r\n{file}\r\n--{b}--\r\n"
    );
    (
        format!("Content-Type: multipart/form-data; boundary={b}\r\n"),
        body,
    )
}

#[test]
fn a_job_file_goes_out_of_the_form_and_back_in_and_bad_files_are_refused_as_text() {
    let cluster = Cluster::start_without_agent();
    let (_web, addr) = start_web(&cluster);
    let addr = addr.as_str();
    let cookie = sign_in(addr, "planner");
    let with_cookie = format!("Cookie: {cookie}\r\n");
    let (code, _, form) = http(addr, "GET", "/new/hobbing", &with_cookie, "");
    assert_eq!(code, 200, "{form}");
    let csrf = csrf_of(&form);

    // Export: the form's job as a TOML file the CLI reads.
    let fields = format!(
        "csrf={csrf}&action=export&job.machine=H01&job.part_number=EX-7&gear.module_mm=2.5&gear.teeth=31&gear.face_width_mm=20&gear.material=C45&gear.fixture_height_mm=100&hob.id=HOB-M3-80"
    );
    let urlencoded = format!("{with_cookie}Content-Type: application/x-www-form-urlencoded\r\n");
    let (code, head, file) = http(addr, "POST", "/new/hobbing", &urlencoded, &fields);
    assert_eq!(code, 200, "{head}\n{file}");
    assert!(head.contains("filename=\"EX-7.toml\""), "{head}");
    let table: toml::Table = file.parse().expect("the export is TOML");
    assert_eq!(table["gear"]["teeth"].as_integer(), Some(31));
    assert_eq!(table["gear"]["module_mm"].as_float(), Some(2.5));

    // Import it again: the form holds its values, and the check says the
    // hob does not fit (module 2.5 with a module-3 hob).
    let (headers, body) = multipart(&csrf, &file);
    let (code, _, page) = http(
        addr,
        "POST",
        "/new/import",
        &format!("{with_cookie}{headers}"),
        &body,
    );
    assert_eq!(code, 200, "{page}");
    assert!(page.contains("name=\"gear.teeth\" value=\"31\""), "{page}");
    assert!(page.contains("BASE_PITCH_MISMATCH"), "{page}");

    // Malformed TOML with a script in it: refused, and shown as text.
    let (headers, body) = multipart(&csrf, "[job\npart_number = \"<script>alert(1)</script>\"");
    let (code, _, page) = http(
        addr,
        "POST",
        "/new/import",
        &format!("{with_cookie}{headers}"),
        &body,
    );
    assert_eq!(code, 422, "{page}");
    assert!(page.contains("does not parse"), "{page}");
    assert!(!page.contains("<script>alert"), "{page}");
    // A file the form cannot hold whole is refused, naming what would be lost.
    let multi = examples::example("multi_gear_840d.toml");
    let (headers, body) = multipart(&csrf, &multi);
    let (code, _, page) = http(
        addr,
        "POST",
        "/new/import",
        &format!("{with_cookie}{headers}"),
        &body,
    );
    assert_eq!(code, 422, "{page}");
    assert!(page.contains("units"), "{page}");
    // An oversized upload is refused before it is read.
    let big = format!("# {}\n", "x".repeat(70 * 1024));
    let (headers, body) = multipart(&csrf, &big);
    let (code, _, _) = http(
        addr,
        "POST",
        "/new/import",
        &format!("{with_cookie}{headers}"),
        &body,
    );
    assert_eq!(code, 413);
    // Without the session's token, nothing is imported.
    let (headers, body) = multipart("forged", &file);
    let (code, _, _) = http(
        addr,
        "POST",
        "/new/import",
        &format!("{with_cookie}{headers}"),
        &body,
    );
    assert_eq!(code, 403);
}
