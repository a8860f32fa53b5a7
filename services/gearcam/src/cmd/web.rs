//! `gearcam web`: the planning office's page ([`crate::web`]) on the bus;
//! `gearcam web-user`: adds a user of the page or sets their password.

use std::io::BufRead;
use std::net::SocketAddr;
use std::path::Path;
use std::process::ExitCode;

use gearcam_bus::{cancel_on_signal, Bus, BusArgs};
use gearcam_proto::MachineId;

use crate::cmd::join_bus;
use crate::web::auth::{self, Auth, Role, User, Users};
use crate::web::new::LocalCheck;

/// The users file's name in the data directory.
pub const USERS_FILE: &str = "web-users.toml";

pub async fn web(
    listen: SocketAddr,
    users: &Path,
    data: &Path,
    bus_args: &BusArgs,
) -> anyhow::Result<ExitCode> {
    let auth = match Auth::load(users) {
        Ok(auth) => auth,
        Err(e) => {
            return Ok(crate::output::fail(
                crate::exit::USAGE,
                &[],
                &format!("gearcam web: {e}; add a user with `gearcam web-user NAME --role planner --users {}`", users.display()),
            ))
        }
    };
    let data = &match crate::data_dir::open(data) {
        Ok(data) => data,
        Err(code) => return Ok(code),
    };
    let local = Some(std::sync::Arc::new(LocalCheck::new(
        data,
        crate::cmd::check::template_library(data)?,
    )));
    let bus = join_bus(bus_args).await?;
    let served = serve(bus.clone(), auth, local, listen, cancel_on_signal()).await;
    bus.close().await;
    served?;
    Ok(ExitCode::SUCCESS)
}

/// Serves the page for `auth`'s users on `bus` until `stop`.
pub async fn serve(
    bus: Bus,
    auth: Auth,
    local: crate::web::new::Local,
    listen: SocketAddr,
    stop: tokio_util::sync::CancellationToken,
) -> anyhow::Result<()> {
    crate::web::serve(crate::web::Web { bus, auth, local }, listen, stop).await
}

/// The page beside the services of `up` and `demo`, on their bus: the
/// data directory's users (on the first start, one per role with a random
/// password, written once to `DATA/web-passwords.txt`; the operator of
/// every machine served), listening on `listen`, or on any free port of its
/// host when that one is taken. Prints the address and where the users are.
pub async fn beside(
    services: &crate::embedded::Embedded,
    data: &Path,
    listen: SocketAddr,
    stop: tokio_util::sync::CancellationToken,
) -> anyhow::Result<tokio::task::JoinHandle<anyhow::Result<()>>> {
    let machines: Vec<MachineId> = services.machines.iter().map(|m| m.id.clone()).collect();
    let users = data.join(USERS_FILE);
    let passwords = data.join(PASSWORDS_FILE);
    let made = auth::first_users(&users, &passwords, &machines)?;
    let auth = Auth::load(&users)?;
    let local = Some(std::sync::Arc::new(LocalCheck::new(
        data,
        crate::cmd::check::template_library(data)?,
    )));
    let listener = match tokio::net::TcpListener::bind(listen).await {
        Ok(l) => l,
        Err(_) => tokio::net::TcpListener::bind(SocketAddr::new(listen.ip(), 0)).await?,
    };
    if made {
        crate::outln!(
            "  web page users: planner, operator, admin, supervisor; first passwords in {} (change them with gearcam web-user)",
            passwords.display()
        );
    } else {
        crate::outln!("  web page users: {}", users.display());
    }
    let web = crate::web::Web {
        bus: services.bus.clone(),
        auth,
        local,
    };
    Ok(tokio::spawn(crate::web::serve_on(listener, web, stop)))
}

/// The file of the first users' passwords in the data directory.
pub const PASSWORDS_FILE: &str = "web-passwords.txt";

/// `gearcam web-user NAME --role ROLE [--machine M]…`: the password is read
/// from the first line of standard input and kept only as its Argon2 hash.
pub fn web_user(users_path: &Path, name: &str, role: &str, machines: Vec<MachineId>) -> ExitCode {
    let usage = |msg: String| crate::output::fail(crate::exit::USAGE, &[], &msg);
    let Some(role) = Role::parse(role) else {
        let roles: Vec<_> = Role::ALL.iter().map(|r| r.as_str()).collect();
        return usage(format!(
            "gearcam web-user: --role: expected one of {}, got {role:?}",
            roles.join(", ")
        ));
    };
    if name.is_empty() || name.len() > 64 || gearcam_proto::keys::user_chunk(name) != name {
        return usage(format!(
            "gearcam web-user: NAME: expected 1 to 64 characters without / * $ ? # or a leading @, got {name:?}"
        ));
    }
    let mut password = String::new();
    if std::io::stdin().lock().read_line(&mut password).is_err() {
        return usage("gearcam web-user: could not read the password from standard input".into());
    }
    let password = password.trim_end_matches(['\r', '\n']);
    if password.chars().count() < 8 {
        return usage(format!(
            "gearcam web-user: password (standard input): expected at least 8 characters, got {}",
            password.chars().count()
        ));
    }
    let mut users = if users_path.exists() {
        match Users::load(users_path) {
            Ok(u) => u,
            Err(e) => return usage(format!("gearcam web-user: {e}")),
        }
    } else {
        Users::default()
    };
    users.set(User {
        name: name.to_string(),
        role,
        machines,
        password: auth::hash_password(password),
    });
    if let Err(e) = users.save(users_path) {
        return crate::output::fail(
            crate::exit::UNREACHABLE,
            &[],
            &format!("gearcam web-user: writing {}: {e}", users_path.display()),
        );
    }
    crate::outln!(
        "gearcam web-user: {name} ({}) in {}; a running page takes it when restarted",
        role.as_str(),
        users_path.display()
    );
    ExitCode::SUCCESS
}
