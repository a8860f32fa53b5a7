//! Who may use the page and what they may do: users with a role, signed in
//! with a password kept only as a slow hash (Argon2id), a session in an
//! HTTP-only, secure, same-site cookie, and a CSRF token on every change.
//!
//! The roles are those of the bus's access control: a **planner** submits
//! jobs and reads; an **operator** also changes the current program of the
//! machines they are given (rollback, adopt, replace); an **admin** also
//! changes the knowledge base; a **supervisor** may do both. Every page
//! needs a signed-in user; every change (a `POST`) needs the session's CSRF
//! token in its form and, when the browser sends one, an `Origin` of this
//! server.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::time::Instant;

use argon2::password_hash::rand_core::{OsRng, RngCore};
use argon2::password_hash::{PasswordHash, PasswordHasher, PasswordVerifier, SaltString};
use argon2::Argon2;
use axum::extract::{FromRequest, Request, State};
use axum::http::{header, HeaderMap, Method, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Redirect, Response};
use axum_extra::extract::cookie::{Cookie, CookieJar, SameSite};
use gearcam_proto::MachineId;
use maud::html;
use serde::{Deserialize, Serialize};

use super::{page, Web};

/// The session cookie's name.
pub const SESSION_COOKIE: &str = "gearcam_session";
/// The form field that carries the CSRF token.
pub const CSRF_FIELD: &str = "csrf";
/// Password checks (Argon2, about 19 MiB each) running at once at most.
const PASSWORD_CHECKS_AT_ONCE: usize = 2;
/// A session ends after this long without a request.
const IDLE: Duration = Duration::from_secs(8 * 3600);

/// A user's role, as on the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// Submits jobs and reads everything.
    Planner,
    /// A planner who also changes the current program of their machines.
    Operator,
    /// A planner who also changes the knowledge base.
    Admin,
    /// Operator and admin together.
    Supervisor,
}

impl Role {
    /// Every role, in the order the page lists them.
    pub const ALL: [Role; 4] = [Role::Planner, Role::Operator, Role::Admin, Role::Supervisor];

    /// The role's name as written in the users file.
    pub fn as_str(self) -> &'static str {
        match self {
            Role::Planner => "planner",
            Role::Operator => "operator",
            Role::Admin => "admin",
            Role::Supervisor => "supervisor",
        }
    }

    /// The role named `s`.
    pub fn parse(s: &str) -> Option<Role> {
        Role::ALL.into_iter().find(|r| r.as_str() == s)
    }

    /// What the role may do, in a few words (the sign-in page and README).
    pub fn rights(self) -> &'static str {
        match self {
            Role::Planner => "submit jobs, read jobs, programs and the knowledge base",
            Role::Operator => {
                "a planner's rights, and roll back, adopt or replace the programs of their machines"
            }
            Role::Admin => "a planner's rights, and edit the knowledge base",
            Role::Supervisor => "an operator's and an admin's rights on every machine",
        }
    }
}

/// One user of the page, as in the users file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct User {
    /// The sign-in name; also the name the bus records as the author of
    /// the user's changes.
    pub name: String,
    /// The role.
    pub role: Role,
    /// An operator's machines (empty: none; a supervisor has every machine).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub machines: Vec<MachineId>,
    /// The password's Argon2id hash in PHC form (`$argon2id$…`).
    pub password: String,
}

impl User {
    /// True when the user may submit jobs and read (every role).
    pub fn may_submit(&self) -> bool {
        true
    }

    /// True when the user may change the current program of `machine`.
    pub fn may_change_program(&self, machine: &MachineId) -> bool {
        match self.role {
            Role::Supervisor => true,
            Role::Operator => self.machines.contains(machine),
            Role::Planner | Role::Admin => false,
        }
    }

    /// True when the user may change the knowledge base.
    pub fn may_edit_kb(&self) -> bool {
        matches!(self.role, Role::Admin | Role::Supervisor)
    }
}

/// The users file: `[[user]]` tables of [`User`].
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Users {
    /// Every user.
    #[serde(default, rename = "user")]
    pub users: Vec<User>,
}

impl Users {
    /// Reads the users file at `path`.
    pub fn load(path: &Path) -> anyhow::Result<Users> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| anyhow::anyhow!("the users file {}: {e}", path.display()))?;
        let users: Users = toml::from_str(&text)
            .map_err(|e| anyhow::anyhow!("the users file {}: {e}", path.display()))?;
        for u in &users.users {
            PasswordHash::new(&u.password).map_err(|e| {
                anyhow::anyhow!(
                    "the users file {}: user {:?}: password: expected an Argon2 hash ($argon2id$…), got {:?} ({e})",
                    path.display(),
                    u.name,
                    u.password.chars().take(12).collect::<String>()
                )
            })?;
        }
        Ok(users)
    }

    /// Writes the users file to `path` (readable by its owner only).
    pub fn save(&self, path: &Path) -> anyhow::Result<()> {
        let text = toml::to_string(self)?;
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        let tmp = path.with_extension("tmp");
        let _ = std::fs::remove_file(&tmp);
        write_private(&tmp, text.as_bytes())?;
        std::fs::rename(&tmp, path)?;
        Ok(())
    }

    /// Adds `user`, or replaces the user of the same name.
    pub fn set(&mut self, user: User) {
        match self.users.iter_mut().find(|u| u.name == user.name) {
            Some(u) => *u = user,
            None => self.users.push(user),
        }
    }

    /// The user `name` when `password` is theirs.
    pub fn verify(&self, name: &str, password: &str) -> Option<&User> {
        let user = self.users.iter().find(|u| u.name == name);
        // Verify against some hash even for an unknown name, so the time
        // taken does not tell which names exist.
        let hash = user.map_or(DUMMY_HASH, |u| u.password.as_str());
        let ok = PasswordHash::new(hash)
            .map(|h| {
                Argon2::default()
                    .verify_password(password.as_bytes(), &h)
                    .is_ok()
            })
            .unwrap_or(false);
        user.filter(|_| ok)
    }
}

/// The hash of a password nobody has, checked for an unknown user name.
const DUMMY_HASH: &str = "$argon2id$v=19$m=19456,t=2,p=1$c29tZXNhbHRzb21lc2FsdA$0tbXk3aPqB1YVaVCVHHIaOgVjEySvq4hiOt0bxmTbnk";

/// Writes `bytes` to a new file `path` readable by its owner only from
/// the start (never for a moment by others); an existing file is refused.
#[cfg(unix)]
fn write_private(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    use std::os::unix::fs::OpenOptionsExt;
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o600)
        .open(path)?;
    f.write_all(bytes)?;
    f.sync_all()
}

#[cfg(not(unix))]
fn write_private(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)?;
    f.write_all(bytes)?;
    f.sync_all()
}

/// The Argon2id hash (PHC form, a fresh random salt) of `password`.
pub fn hash_password(password: &str) -> String {
    let salt = SaltString::generate(&mut OsRng);
    Argon2::default()
        .hash_password(password.as_bytes(), &salt)
        .expect("Argon2 with its default parameters hashes any password")
        .to_string()
}

/// `n` random bytes from the operating system, as lowercase hex.
pub fn random_hex(n: usize) -> String {
    let mut bytes = vec![0u8; n];
    OsRng.fill_bytes(&mut bytes);
    hex::encode(bytes)
}

/// A signed-in user's session.
#[derive(Debug, Clone)]
pub struct Session {
    /// The user.
    pub user: User,
    /// The token every change must carry.
    pub csrf: String,
    last_seen: Instant,
}

/// The sessions of signed-in users, by the cookie's random token.
#[derive(Debug, Clone, Default)]
pub struct Sessions {
    inner: Arc<Mutex<HashMap<String, Session>>>,
}

impl Sessions {
    fn start(&self, user: User) -> String {
        let token = random_hex(32);
        let session = Session {
            user,
            csrf: random_hex(32),
            last_seen: Instant::now(),
        };
        self.inner
            .lock()
            .expect("sessions lock")
            .insert(token.clone(), session);
        token
    }

    fn get(&self, token: &str) -> Option<Session> {
        let mut map = self.inner.lock().expect("sessions lock");
        map.retain(|_, s| s.last_seen.elapsed() < IDLE);
        let s = map.get_mut(token)?;
        s.last_seen = Instant::now();
        Some(s.clone())
    }

    fn end(&self, token: &str) {
        self.inner.lock().expect("sessions lock").remove(token);
    }
}

/// Where the users come from.
#[derive(Debug, Clone)]
pub struct Auth {
    /// The users file.
    pub path: PathBuf,
    /// Its users, read at start.
    pub users: Arc<Users>,
    /// The signed-in sessions.
    pub sessions: Sessions,
    /// Permits for password checks running at once.
    pub checking: Arc<tokio::sync::Semaphore>,
}

impl Auth {
    /// The users of the file at `path`.
    pub fn load(path: &Path) -> anyhow::Result<Auth> {
        Ok(Auth {
            path: path.to_path_buf(),
            users: Arc::new(Users::load(path)?),
            sessions: Sessions::default(),
            checking: Arc::new(tokio::sync::Semaphore::new(PASSWORD_CHECKS_AT_ONCE)),
        })
    }
}

/// The sign-in form.
#[derive(Debug, Deserialize)]
pub struct SignIn {
    name: String,
    password: String,
    #[serde(default)]
    next: String,
}

/// `GET /signin`.
pub async fn signin_page(axum::extract::Query(q): axum::extract::Query<NextPage>) -> Response {
    signin_form(&q.next, None).into_response()
}

/// Where to go after signing in.
#[derive(Debug, Default, Deserialize)]
pub struct NextPage {
    #[serde(default)]
    next: String,
}

fn signin_form(next: &str, refused: Option<&str>) -> (StatusCode, maud::Markup) {
    let status = if refused.is_some() {
        StatusCode::UNAUTHORIZED
    } else {
        StatusCode::OK
    };
    let body = html! {
        h1 { "Sign in" }
        @if let Some(r) = refused { p.refused role="alert" { (r) } }
        form method="post" action="/signin" {
            input type="hidden" name="next" value=(next);
            p { label { "Name " input name="name" autocomplete="username" required autofocus; } }
            p { label { "Password " input type="password" name="password" autocomplete="current-password" required; } }
            p { button type="submit" id="signin" { "Sign in" } }
        }
        h2 { "Roles" }
        dl { @for r in Role::ALL { dt { (r.as_str()) } dd { (r.rights()) } } }
    };
    (status, page("Sign in", None, body))
}

/// `POST /signin`: a session for the right password, else the form again.
pub async fn signin(
    State(web): State<Web>,
    headers: HeaderMap,
    jar: CookieJar,
    axum::Form(form): axum::Form<SignIn>,
) -> Response {
    if !same_origin(&headers) {
        return refuse(
            StatusCode::FORBIDDEN,
            "a sign-in from another site is refused",
        );
    }
    let users = web.auth.users.clone();
    let (name, password) = (form.name.clone(), form.password.clone());
    // Argon2 is slow and takes memory on purpose: off the async threads,
    // and only a few at once, so a flood of sign-ins queues instead of
    // exhausting the memory.
    let Ok(_permit) = web.auth.checking.clone().acquire_owned().await else {
        return refuse(StatusCode::SERVICE_UNAVAILABLE, "the page is stopping");
    };
    let user = tokio::task::spawn_blocking(move || users.verify(&name, &password).cloned())
        .await
        .ok()
        .flatten();
    let Some(user) = user else {
        return signin_form(&form.next, Some("Unknown name or wrong password.")).into_response();
    };
    let token = web.auth.sessions.start(user);
    let cookie = Cookie::build((SESSION_COOKIE, token))
        .http_only(true)
        .secure(true)
        .same_site(SameSite::Strict)
        .path("/")
        .build();
    (jar.add(cookie), Redirect::to(safe_next(&form.next))).into_response()
}

/// Only a path on this server (`/…`, not `//host`) is followed after sign-in.
fn safe_next(next: &str) -> &str {
    // A path of this server only: `/` then a path character, never a
    // second `/` or `\` (another host), no control character, space or
    // encoded control character (browsers drop tabs and newlines, turning
    // `/<tab>/host` into `//host`).
    let path_char = |c: char| c.is_ascii_alphanumeric() || "/_.~%?=&-".contains(c);
    let on_this_server = next.starts_with('/')
        && !matches!(next.chars().nth(1), Some('/' | '\\'))
        && next.chars().all(path_char)
        && !next.contains("%0");
    if on_this_server {
        next
    } else {
        "/"
    }
}

/// `POST /signout`.
pub async fn signout(State(web): State<Web>, jar: CookieJar, form: CsrfForm<Empty>) -> Response {
    let _ = form;
    if let Some(c) = jar.get(SESSION_COOKIE) {
        web.auth.sessions.end(c.value());
    }
    (
        jar.remove(Cookie::build(SESSION_COOKIE).path("/")),
        Redirect::to("/signin"),
    )
        .into_response()
}

/// A form with no fields besides its CSRF token.
#[derive(Debug, Default, Deserialize)]
pub struct Empty {}

/// The middleware every page but sign-in goes through: the session of the
/// cookie (put in the request's extensions), else a redirect to sign in;
/// for a change, an `Origin` of another site is refused.
pub async fn require_session(
    State(web): State<Web>,
    jar: CookieJar,
    mut req: Request,
    next: Next,
) -> Response {
    if req.method() != Method::GET && req.method() != Method::HEAD && !same_origin(req.headers()) {
        return refuse(
            StatusCode::FORBIDDEN,
            "a change from another site is refused",
        );
    }
    let session = jar
        .get(SESSION_COOKIE)
        .and_then(|c| web.auth.sessions.get(c.value()));
    match session {
        Some(s) => {
            req.extensions_mut().insert(s);
            next.run(req).await
        }
        None => {
            let here = req
                .uri()
                .path_and_query()
                .map(|p| p.as_str().to_string())
                .unwrap_or_default();
            let to = format!("/signin?next={}", urlencode(&here));
            Redirect::to(&to).into_response()
        }
    }
}

/// True when the request has no `Origin`, or one whose host is the
/// request's `Host`.
fn same_origin(headers: &HeaderMap) -> bool {
    let Some(origin) = headers.get(header::ORIGIN).and_then(|o| o.to_str().ok()) else {
        return true;
    };
    let host = headers
        .get(header::HOST)
        .and_then(|h| h.to_str().ok())
        .unwrap_or("");
    let origin_host = origin
        .split_once("://")
        .map_or("", |(_, rest)| rest.trim_end_matches('/'));
    !host.is_empty() && origin_host == host
}

/// `s` percent-encoded for a query value.
pub fn urlencode(s: &str) -> String {
    s.bytes()
        .map(|b| match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'_' | b'.' | b'~' | b'/' => {
                (b as char).to_string()
            }
            _ => format!("%{b:02X}"),
        })
        .collect()
}

/// A page saying what was refused.
pub fn refuse(status: StatusCode, why: &str) -> Response {
    (
        status,
        page(
            "Refused",
            None,
            html! { h1 { "Refused" } p.refused role="alert" { (why) } },
        ),
    )
        .into_response()
}

/// A change's form of type `T`, accepted only with the session's CSRF
/// token in its `csrf` field. The signed-in session comes with it.
#[derive(Debug)]
pub struct CsrfForm<T> {
    /// The session that sent it.
    pub session: Session,
    /// The form's fields.
    pub form: T,
}

impl<T, S> FromRequest<S> for CsrfForm<T>
where
    T: serde::de::DeserializeOwned,
    S: Send + Sync,
{
    type Rejection = Response;

    async fn from_request(req: Request, state: &S) -> Result<Self, Self::Rejection> {
        let session = req
            .extensions()
            .get::<Session>()
            .cloned()
            .ok_or_else(|| refuse(StatusCode::UNAUTHORIZED, "sign in first"))?;
        let bytes = axum::body::Bytes::from_request(req, state)
            .await
            .map_err(IntoResponse::into_response)?;
        check_csrf(&session, &bytes)?;
        let form = serde_urlencoded::from_bytes::<T>(&bytes)
            .map_err(|e| refuse(StatusCode::UNPROCESSABLE_ENTITY, &format!("the form: {e}")))?;
        Ok(CsrfForm { session, form })
    }
}

/// Refuses a change whose form does not carry the session's CSRF token.
pub fn check_csrf(session: &Session, body: &[u8]) -> Result<(), Response> {
    #[derive(Deserialize)]
    struct Token {
        #[serde(default)]
        csrf: String,
    }
    let given = serde_urlencoded::from_bytes::<Token>(body)
        .map(|t| t.csrf)
        .unwrap_or_default();
    csrf_matches(session, &given)
}

/// Refuses a change whose token `given` is not the session's.
pub fn csrf_matches(session: &Session, given: &str) -> Result<(), Response> {
    if !given.is_empty() && constant_time_eq(given.as_bytes(), session.csrf.as_bytes()) {
        Ok(())
    } else {
        Err(refuse(
            StatusCode::FORBIDDEN,
            "the form's CSRF token is missing or not this session's: reload the page and try again",
        ))
    }
}

fn constant_time_eq(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// The hidden field carrying the session's CSRF token, for every form that
/// changes something.
pub fn csrf_input(session: &Session) -> maud::Markup {
    html! { input type="hidden" name=(CSRF_FIELD) value=(session.csrf); }
}

/// Creates the users file at `path` with one user per role and a random
/// password each, when it does not exist: the passwords are written once
/// to `passwords` (readable by its owner only), never to the users file.
/// The operator is given `machines`.
pub fn first_users(path: &Path, passwords: &Path, machines: &[MachineId]) -> anyhow::Result<bool> {
    if path.exists() {
        return Ok(false);
    }
    let mut users = Users::default();
    let mut list = String::from(
        "# The page's first users and their passwords. Change them with\n# `gearcam web-user NAME --role ROLE` and delete this file.\n",
    );
    for role in Role::ALL {
        let password = random_hex(8);
        list.push_str(&format!("{} {password}\n", role.as_str()));
        users.set(User {
            name: role.as_str().to_string(),
            role,
            machines: if role == Role::Operator {
                machines.to_vec()
            } else {
                Vec::new()
            },
            password: hash_password(&password),
        });
    }
    users.save(path)?;
    write_private(passwords, list.as_bytes())?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_password_verifies_only_against_its_own_hash() {
        let mut users = Users::default();
        users.set(User {
            name: "li".into(),
            role: Role::Operator,
            machines: vec![MachineId::new("H01").unwrap()],
            password: hash_password("right horse"),
        });
        assert!(users.verify("li", "right horse").is_some());
        assert!(users.verify("li", "wrong horse").is_none());
        assert!(users.verify("wu", "right horse").is_none());
        assert!(users.users[0].password.starts_with("$argon2id$"));
    }

    #[test]
    fn rights_follow_the_role_and_an_operators_machines() {
        let h01 = MachineId::new("H01").unwrap();
        let h02 = MachineId::new("H02").unwrap();
        let user = |role, machines: Vec<MachineId>| User {
            name: "x".into(),
            role,
            machines,
            password: String::new(),
        };
        assert!(!user(Role::Planner, vec![]).may_change_program(&h01));
        assert!(user(Role::Operator, vec![h01.clone()]).may_change_program(&h01));
        assert!(!user(Role::Operator, vec![h01.clone()]).may_change_program(&h02));
        assert!(user(Role::Supervisor, vec![]).may_change_program(&h02));
        assert!(!user(Role::Operator, vec![h01]).may_edit_kb());
        assert!(user(Role::Admin, vec![]).may_edit_kb());
    }

    #[test]
    fn only_a_path_on_this_server_is_followed_after_sign_in() {
        assert_eq!(safe_next("/jobs/J1"), "/jobs/J1");
        assert_eq!(safe_next("//evil.example/"), "/");
        assert_eq!(safe_next("https://evil.example/"), "/");
        assert_eq!(safe_next("/\\evil"), "/");
        assert_eq!(safe_next("/\t/evil.example"), "/");
        assert_eq!(safe_next("/%09/evil.example"), "/");
        assert_eq!(safe_next("/%0A"), "/");
        assert_eq!(safe_next("/?state=failed&q=SP-1"), "/?state=failed&q=SP-1");
    }

    #[test]
    fn a_change_from_another_origin_is_refused() {
        let mut h = HeaderMap::new();
        h.insert(header::HOST, "127.0.0.1:8080".parse().unwrap());
        assert!(same_origin(&h));
        h.insert(header::ORIGIN, "http://127.0.0.1:8080".parse().unwrap());
        assert!(same_origin(&h));
        h.insert(header::ORIGIN, "http://evil.example".parse().unwrap());
        assert!(!same_origin(&h));
    }
}
