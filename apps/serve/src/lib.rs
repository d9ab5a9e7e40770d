//! `sheetform serve`: a local web editor over the same library pipelines as the CLI.
//!
//! An [axum] server on the loopback interface serves the editor's front end (embedded
//! in the binary: our files from `web/src/`, three.js from npm, see `build.rs`) and a
//! small JSON API over [`sheetform::pipeline`]:
//!
//! | route | what |
//! |---|---|
//! | `POST /api/bend?dir=…` | a bend scene in (its assets read relative to `dir`, inside the served directory; every scene route takes it), the bent sheet (arrays), the pattern SVG and the report out ([`sheetform::pipeline::run_bend`] with [`OutputSet::Preview`](sheetform::pipeline::OutputSet)) |
//! | `POST /api/bend/file/{name}` | one of the files `sheetform bend` writes (OBJ, GLB, STL, SVG, DXF, PDF), for download |
//! | `POST /api/slit` | a slit scene in, the bent sheet, its pattern and the report (per-strip gaps) out ([`sheetform::pipeline::run_slit`], preview outputs) |
//! | `POST /api/slit/file/{name}` | one of the files `sheetform slit` writes, for download |
//! | `POST /api/ffd` | an FFD scene in, resumed from the last design the server restored (only the deformations after those the two scenes share are restored); progress lines while it runs (closing the connection cancels), then the restored panels, the plain FFD, both angle-defect maps, the deformed lattice, the pattern and the report ([`sheetform::pipeline::run_ffd`], preview outputs), as NDJSON |
//! | `POST /api/ffd/file/{name}` | one of the files `sheetform ffd` writes, for download |
//! | `POST /api/photo?dir=…` | a photo annotation in (its photograph read relative to `dir`), the reconstructed model, its pattern and the report out ([`sheetform::pipeline::run_photo`], preview outputs) |
//! | `POST /api/photo/file/{name}?dir=…` | one of the files `sheetform photo` writes, for download |
//! | `POST /api/mesh?name=…` | a mesh file's bytes in (OBJ, PLY, STL, OFF), its developability ([`sheetform::pipeline::run_check`]), the flattened model, its pattern and both reports out ([`sheetform::pipeline::run_flatten`], preview outputs) |
//! | `POST /api/mesh/file/{name}?name=…` | one of the files `sheetform flatten` writes, for download |
//! | `GET /api/files` | the scene files (`*.json`, by mode), the meshes and the photographs under the served directory (`truncated` when a bound of the listing left some out) |
//! | `GET /api/files/{path}` / `PUT /api/files/{path}` | open / save a scene file, confined to the served directory |
//! | `PUT /api/photos/{name}` | a PNG or JPEG chosen from disk, kept as `photos/NAME` (never replacing a file) |
//! | `POST /api/relocate?from=…&to=…` | a scene in, the asset paths that name the same files once the scene is saved in `to` instead of `from` out ([`sheetform::pipeline::relocated_scene_assets`]; the editor's "save as") |
//!
//! On loopback (the default) a request whose `Host` or `Origin` names another machine is
//! refused (DNS rebinding, cross-site posts). Every request is bounded ([`ServeOptions::max_request_bytes`]), and so
//! are the bodies held at once over all requests ([`ServeOptions::max_buffered_bytes`]),
//! the time a client may take to send its headers and its body
//! ([`ServeOptions::header_read_timeout`], [`ServeOptions::body_read_timeout`]) or to take
//! a reply ([`ServeOptions::write_timeout`]) and the connections open at once
//! ([`ServeOptions::max_connections`]). Solves, and the parsing
//! of the scenes they solve, run on a blocking pool at most
//! [`ServeOptions::max_concurrent_solves`] at a time, and a malformed, hostile or failing
//! request gets an error reply (`{"error": {"kind", "message"}}`, with the report when a
//! shape is inadmissible) while the server keeps serving. The library prints nothing:
//! the caller is told the address through [`Server::local_address`].

#![warn(missing_docs)]

mod api;
mod array_reply;
mod assets;
pub use assets::EDITOR_EMBEDDED;
mod ffd;
mod files;
mod mesh;
mod photo;
mod slit;
mod write_timeout;

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// Largest request body by default (64 MiB, the largest file the editor opens from the
/// served directory, `sheetform::io::MAX_SCENE_FILE_BYTES`, so that a mesh it opens can
/// be sent back): a scene file is far smaller.
pub const DEFAULT_MAX_REQUEST_BYTES: usize = 64 << 20;

/// Most bytes of request bodies held at once over all requests by default (256 MiB: four
/// of the largest bodies).
pub const DEFAULT_MAX_BUFFERED_BYTES: usize = 4 * DEFAULT_MAX_REQUEST_BYTES;

/// How the editor is served.
#[derive(Debug, Clone)]
pub struct ServeOptions {
    /// Interface to listen on: loopback unless the user asks for another explicitly.
    pub host: IpAddr,
    /// Port; 0 picks a free one.
    pub port: u16,
    /// The directory whose scene files the editor may open and save (and whose assets
    /// the scenes may read).
    pub root: PathBuf,
    /// Largest request body (bytes).
    pub max_request_bytes: usize,
    /// Most bytes of request bodies held in memory at once, over all requests (default
    /// [`DEFAULT_MAX_BUFFERED_BYTES`]; never less than `max_request_bytes`). A body takes
    /// its declared length (`Content-Length`) from this budget before it is read, or, when
    /// it declares none (chunked), what its buffer holds as it grows, and gives it back
    /// when its request is answered, so requests waiting for a solve slot do not pile up
    /// bodies; a request that finds the budget spent is refused at once (503, kind
    /// `busy`).
    pub max_buffered_bytes: usize,
    /// Solves running at the same time; more wait their turn.
    pub max_concurrent_solves: usize,
    /// Longest time a client may take to send a request's headers, and longest a kept-
    /// alive connection waits for its next request (default 30 s): the connection is
    /// then closed ([`Server`]; [`router`] alone does not read connections).
    pub header_read_timeout: Duration,
    /// Longest time a client may take to send a request's body once its headers are in
    /// (default 60 s): the request is then answered 408 (kind `timeout`) and its
    /// connection closed.
    pub body_read_timeout: Duration,
    /// Longest time a reply may wait for the client to take more of it (default 30 s):
    /// a client that stops reading has its connection closed ([`Server`]). The clock
    /// runs only while a write waits on the client, so a slow reader that keeps reading
    /// and a reply waiting on its solve are never cut off.
    pub write_timeout: Duration,
    /// Most connections open at once (default 256): more wait in the system's queue of
    /// connections until one closes ([`Server`]).
    pub max_connections: usize,
}

impl Default for ServeOptions {
    fn default() -> Self {
        Self {
            host: IpAddr::V4(Ipv4Addr::LOCALHOST),
            port: 0,
            root: PathBuf::from("."),
            max_request_bytes: DEFAULT_MAX_REQUEST_BYTES,
            max_buffered_bytes: DEFAULT_MAX_BUFFERED_BYTES,
            max_concurrent_solves: 2,
            header_read_timeout: Duration::from_secs(30),
            body_read_timeout: Duration::from_secs(60),
            write_timeout: Duration::from_secs(30),
            max_connections: 256,
        }
    }
}

/// Errors starting or running the server.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The served directory is not a directory.
    #[error("the served directory {path}: {message}")]
    Root {
        /// The directory given.
        path: String,
        /// Why it cannot be served.
        message: String,
    },
    /// The address cannot be bound or the server failed.
    #[error("{0}")]
    Io(#[from] std::io::Error),
}

/// What every request handler shares.
#[derive(Debug)]
pub(crate) struct AppState {
    /// The served directory (canonical).
    pub root: PathBuf,
    /// Bounds the solves running at once (a permit stays with its solve until it ends,
    /// also when the client has gone).
    pub solves: Arc<tokio::sync::Semaphore>,
    /// Its size: the most slots one solve may take.
    pub solve_slots: usize,
    /// The last FFD design restored, to resume the next run from (a drag appends a
    /// deformation: only that one is restored; see `ffd.rs`).
    pub last_ffd_design: std::sync::Mutex<Option<Arc<sheetform::ffd::FfdDesign>>>,
    /// The bytes of request bodies held at once, in [`api::BUDGET_UNIT`]s: a body takes
    /// its share before it is read and gives it back when dropped (`api::Buffered`).
    pub body_budget: Arc<tokio::sync::Semaphore>,
    /// The budget's size (bytes), for messages.
    pub body_budget_bytes: usize,
    /// Largest request body (bytes).
    pub max_request_bytes: usize,
    /// Longest time a body may take to arrive.
    pub body_read_timeout: Duration,
}

/// The editor's routes over a served directory (for tests and embedding; [`Server`]
/// serves them).
///
/// # Errors
/// [`ServeError::Root`] when `options.root` is not a directory.
pub fn router(options: &ServeOptions) -> Result<axum::Router, ServeError> {
    let root = options.root.canonicalize().map_err(|e| ServeError::Root {
        path: options.root.display().to_string(),
        message: e.to_string(),
    })?;
    if !root.is_dir() {
        return Err(ServeError::Root {
            path: options.root.display().to_string(),
            message: "not a directory".into(),
        });
    }
    let budget_bytes = options.max_buffered_bytes.max(options.max_request_bytes);
    let state = Arc::new(AppState {
        root,
        solves: Arc::new(tokio::sync::Semaphore::new(options.max_concurrent_solves.max(1))),
        solve_slots: options.max_concurrent_solves.max(1),
        last_ffd_design: std::sync::Mutex::new(None),
        body_budget: Arc::new(tokio::sync::Semaphore::new(
            api::budget_units(budget_bytes).min(tokio::sync::Semaphore::MAX_PERMITS),
        )),
        body_budget_bytes: budget_bytes,
        max_request_bytes: options.max_request_bytes,
        body_read_timeout: options.body_read_timeout,
    });
    let router = axum::Router::new()
        .merge(assets::routes())
        .merge(api::routes())
        .merge(mesh::routes())
        .merge(slit::routes())
        .merge(ffd::routes())
        .merge(photo::routes())
        .merge(files::routes())
        .layer(axum::extract::DefaultBodyLimit::max(options.max_request_bytes))
        .with_state(state);
    // On loopback (the default), only pages of this machine may talk to the server: a
    // web page elsewhere that points its own host name at 127.0.0.1 (DNS rebinding) or
    // posts across origins is refused. With an explicit `--host` the user chose to serve
    // other machines, whose names cannot be known here.
    Ok(if options.host.is_loopback() {
        router.layer(axum::middleware::from_fn(this_machine_only))
    } else {
        router
    })
}

/// Whether an authority (`host[:port]`) names this machine's loopback interface.
fn is_loopback_authority(authority: &str) -> bool {
    let host = if let Some(rest) = authority.strip_prefix('[') {
        rest.split(']').next().unwrap_or("")
    } else {
        authority.split(':').next().unwrap_or("")
    };
    host.eq_ignore_ascii_case("localhost") || host.parse::<IpAddr>().is_ok_and(|address| address.is_loopback())
}

/// Refuses a request whose `Host` or `Origin` header names another machine (absent
/// headers pass: clients other than browsers need not send them).
async fn this_machine_only(request: axum::extract::Request, next: axum::middleware::Next) -> axum::response::Response {
    let headers = request.headers();
    let allowed = |name: axum::http::HeaderName, authority: fn(&str) -> Option<&str>| {
        headers.get(name).is_none_or(|value| {
            value
                .to_str()
                .ok()
                .and_then(authority)
                .is_some_and(is_loopback_authority)
        })
    };
    fn whole(authority: &str) -> Option<&str> {
        Some(authority)
    }
    fn after_scheme(origin: &str) -> Option<&str> {
        origin.split_once("://").map(|(_, rest)| rest)
    }
    if allowed(axum::http::header::HOST, whole) && allowed(axum::http::header::ORIGIN, after_scheme) {
        next.run(request).await
    } else {
        axum::response::IntoResponse::into_response(api::ApiError::new(
            axum::http::StatusCode::FORBIDDEN,
            "invalid_input",
            "the editor answers pages of this machine only (its Host or Origin names another); serve with --host to allow others",
        ))
    }
}

/// What each connection is allowed ([`ServeOptions`]).
#[derive(Debug, Clone, Copy)]
struct ConnectionLimits {
    header_read_timeout: Duration,
    write_timeout: Duration,
    max_connections: usize,
}

/// A bound server, ready to run.
#[derive(Debug)]
pub struct Server {
    runtime: tokio::runtime::Runtime,
    listener: tokio::net::TcpListener,
    router: axum::Router,
    limits: ConnectionLimits,
}

impl Server {
    /// Binds the address (a free port when `options.port` is 0).
    ///
    /// # Errors
    /// The served directory is not one, or the address cannot be bound.
    pub fn bind(options: &ServeOptions) -> Result<Self, ServeError> {
        let router = router(options)?;
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .enable_all()
            .build()?;
        let listener = runtime.block_on(tokio::net::TcpListener::bind(SocketAddr::new(
            options.host,
            options.port,
        )))?;
        Ok(Self {
            runtime,
            listener,
            router,
            limits: ConnectionLimits {
                header_read_timeout: options.header_read_timeout,
                write_timeout: options.write_timeout,
                max_connections: options.max_connections.max(1),
            },
        })
    }

    /// The address the server listens on.
    ///
    /// # Errors
    /// The OS cannot say.
    pub fn local_address(&self) -> Result<SocketAddr, ServeError> {
        Ok(self.listener.local_addr()?)
    }

    /// Serves until `stop` is set (by a Ctrl-C handler, say), finishing the requests
    /// under way.
    ///
    /// # Errors
    /// The server fails.
    pub fn run(self, stop: &'static AtomicBool) -> Result<(), ServeError> {
        let Self {
            runtime,
            listener,
            router,
            limits,
        } = self;
        let stopped = async move {
            while !stop.load(Ordering::SeqCst) {
                tokio::time::sleep(std::time::Duration::from_millis(100)).await;
            }
        };
        runtime.block_on(serve(listener, router, limits, stopped));
        Ok(())
    }
}

/// Accepts connections until `stop` ends, at most `limits.max_connections` open at once
/// (the next is accepted when one closes; until then it waits in the system's queue),
/// each served by hyper's HTTP/1 connection with its header read timeout (`axum::serve`
/// sets none: a client sending its headers a byte at a time held its socket for good)
/// over a socket whose writes give up after the write timeout (hyper has none: a client
/// that never read its reply held its socket for good); then waits for the requests
/// under way.
async fn serve(
    listener: tokio::net::TcpListener,
    router: axum::Router,
    limits: ConnectionLimits,
    stop: impl std::future::Future<Output = ()>,
) {
    let mut http = hyper::server::conn::http1::Builder::new();
    http.timer(hyper_util::rt::TokioTimer::new())
        .header_read_timeout(limits.header_read_timeout);
    let open = Arc::new(tokio::sync::Semaphore::new(limits.max_connections));
    let graceful = hyper_util::server::graceful::GracefulShutdown::new();
    let mut stop = std::pin::pin!(stop);
    loop {
        let slot = tokio::select! {
            slot = open.clone().acquire_owned() => match slot {
                Ok(slot) => slot,
                Err(_) => break,
            },
            () = &mut stop => break,
        };
        let stream = tokio::select! {
            accepted = listener.accept() => match accepted {
                Ok((stream, _)) => stream,
                Err(error) => {
                    accept_failed(error).await;
                    continue;
                }
            },
            () = &mut stop => break,
        };
        // Replies go out at once (no Nagle delay): an edit's round trip is a few small
        // messages, which delayed acknowledgements would hold up by tens of ms.
        if let Err(error) = stream.set_nodelay(true) {
            tracing::debug!(%error, "TCP_NODELAY not set");
        }
        let service = hyper_util::service::TowerToHyperService::new(router.clone());
        let stream = write_timeout::WriteTimeout::new(stream, limits.write_timeout);
        let connection = graceful.watch(http.serve_connection(hyper_util::rt::TokioIo::new(stream), service));
        tokio::spawn(async move {
            if let Err(error) = connection.await {
                tracing::debug!(%error, "connection ended");
            }
            drop(slot);
        });
    }
    drop(listener);
    graceful.shutdown().await;
}

/// After a failed `accept`: a connection that went away is nothing; anything else (too
/// many open files) is waited out for a second, as `axum::serve` does.
async fn accept_failed(error: std::io::Error) {
    use std::io::ErrorKind;
    if matches!(
        error.kind(),
        ErrorKind::ConnectionRefused | ErrorKind::ConnectionAborted | ErrorKind::ConnectionReset
    ) {
        return;
    }
    tracing::error!(%error, "accepting a connection failed");
    tokio::time::sleep(Duration::from_secs(1)).await;
}
