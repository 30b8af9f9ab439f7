//! # gecaro-web
//!
//! The paper's GECARO main page (§4, Figure 2) as a local web app: the
//! robot's table, editable with validation; New, Open, Save of robot files
//! in one folder; a view of the robot at a configuration set with sliders;
//! and, for each of the seven methods, its three functions (identifiable
//! parameters, points generation, identification with progress and plots).
//!
//! The page talks to a JSON API under `/api` (documented in `docs/api.md`).
//! The server listens on 127.0.0.1 only, reads and writes files only inside
//! its folder ([`workspace`]), bounds every request ([`limits`]), and answers
//! bad requests with a 4xx and a JSON message ([`ApiError`]); a panic in a
//! computation becomes a 500 and the server lives on.
//!
//! ```no_run
//! # async fn run() -> Result<(), gecaro_web::Error> {
//! let server = gecaro_web::Server::bind(&gecaro_web::Config {
//!     folder: ".".into(),
//!     port: 8080,
//! })
//! .await?;
//! println!("gecaro at {}", server.url());
//! server.run(std::future::pending()).await
//! # }
//! ```

#![warn(missing_docs)]

mod api;
mod error;
mod folder_files;
mod guard;
mod jobs;
pub mod limits;
mod page;
mod state;
pub mod workspace;

use std::future::Future;
use std::net::{Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::sync::Arc;

use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::routing::get;
use tokio::sync::Semaphore;

pub use api::POST_ROUTES;
pub use error::ApiError;
pub use state::AppState;
pub use workspace::Workspace;

/// Errors of starting or running the server.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The folder cannot be used.
    #[error("cannot serve the folder {}: {source}", .folder.display())]
    Folder {
        /// The folder as given.
        folder: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The port cannot be listened on.
    #[error("cannot listen on 127.0.0.1:{port}: {source} (is another server using it? try --port)")]
    Bind {
        /// The port.
        port: u16,
        /// Why.
        source: std::io::Error,
    },
    /// The server stopped on an error.
    #[error("the server stopped: {0}")]
    Serve(std::io::Error),
}

/// Where to serve.
#[derive(Clone, Debug)]
pub struct Config {
    /// The folder of robot and data files.
    pub folder: PathBuf,
    /// The port on 127.0.0.1 (0: any free port).
    pub port: u16,
}

/// The whole application: the page, the API, and the guard around both.
pub fn router(state: AppState) -> Router {
    Router::new()
        .route("/", get(page::index))
        .route("/js/{*path}", get(page::module))
        .route("/style.css", get(page::style))
        .nest("/api", api::routes())
        .fallback(|| async { ApiError::NotFound("no such page or API route".into()) })
        .layer(DefaultBodyLimit::max(limits::MAX_BODY_BYTES))
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            guard::guard,
        ))
        .with_state(state)
}

/// A server bound to its port, ready to run.
#[derive(Debug)]
pub struct Server {
    listener: tokio::net::TcpListener,
    state: AppState,
    url: String,
    connections: usize,
    header_timeout: std::time::Duration,
}

impl Server {
    /// Binds 127.0.0.1:`port` and opens the folder.
    ///
    /// # Errors
    /// [`Error::Folder`] or [`Error::Bind`].
    pub async fn bind(config: &Config) -> Result<Server, Error> {
        let workspace = Workspace::new(&config.folder).map_err(|source| Error::Folder {
            folder: config.folder.clone(),
            source,
        })?;
        let address = SocketAddr::from((Ipv4Addr::LOCALHOST, config.port));
        let listener = tokio::net::TcpListener::bind(address)
            .await
            .map_err(|source| Error::Bind {
                port: config.port,
                source,
            })?;
        let port = listener
            .local_addr()
            .map_err(|source| Error::Bind {
                port: config.port,
                source,
            })?
            .port();
        let allowed = vec![format!("127.0.0.1:{port}"), format!("localhost:{port}")];
        Ok(Server {
            listener,
            state: AppState::new(workspace, allowed),
            url: format!("http://127.0.0.1:{port}/"),
            connections: connection_limit(),
            header_timeout: limits::HEADER_TIMEOUT,
        })
    }

    /// The same server with other connection bounds (the defaults are
    /// [`connection_limit`] and [`limits::HEADER_TIMEOUT`]): for tests.
    #[must_use]
    pub fn with_connection_bounds(
        mut self,
        connections: usize,
        header_timeout: std::time::Duration,
    ) -> Self {
        self.connections = connections.max(1);
        self.header_timeout = header_timeout;
        self
    }

    /// The page's address.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// The folder served.
    pub fn folder(&self) -> &std::path::Path {
        self.state.workspace().root()
    }

    /// Serves until `shutdown` completes, then lets the requests under way
    /// finish (for up to the header timeout).
    ///
    /// Connections are served by hyper's HTTP/1 server: one whose headers
    /// have not arrived within [`limits::HEADER_TIMEOUT`], or that stays idle
    /// as long between requests, is closed; at most [`connection_limit`]
    /// are open at once (the others wait in the listener's queue), so that
    /// sockets held open cannot exhaust the process's descriptors. A failed
    /// accept (no descriptor left, a connection reset) is retried.
    ///
    /// # Errors
    /// None today; [`Error::Serve`] is kept for listeners that can fail.
    pub async fn run(
        self,
        shutdown: impl Future<Output = ()> + Send + 'static,
    ) -> Result<(), Error> {
        let app = router(self.state);
        let slots = Arc::new(Semaphore::new(self.connections));
        let graceful = hyper_util::server::graceful::GracefulShutdown::new();
        let mut http = hyper::server::conn::http1::Builder::new();
        http.timer(hyper_util::rt::TokioTimer::new())
            .header_read_timeout(self.header_timeout);
        let mut shutdown = std::pin::pin!(shutdown);
        loop {
            let slot = tokio::select! {
                slot = Arc::clone(&slots).acquire_owned() => slot,
                () = &mut shutdown => break,
            };
            let Ok(slot) = slot else { break };
            let accepted = tokio::select! {
                accepted = self.listener.accept() => accepted,
                () = &mut shutdown => break,
            };
            let stream = match accepted {
                Ok((stream, _)) => stream,
                // Out of descriptors, or a connection reset before it was
                // accepted: wait a little and go on.
                Err(_) => {
                    tokio::time::sleep(std::time::Duration::from_millis(20)).await;
                    continue;
                }
            };
            let _ = stream.set_nodelay(true);
            let service = hyper_util::service::TowerToHyperService::new(app.clone());
            let connection = graceful
                .watch(http.serve_connection(hyper_util::rt::TokioIo::new(stream), service));
            tokio::spawn(async move {
                let _ = connection.await;
                drop(slot);
            });
        }
        tokio::select! {
            () = graceful.shutdown() => {}
            () = tokio::time::sleep(self.header_timeout) => {}
        }
        Ok(())
    }
}

/// Most connections served at once: [`limits::MAX_CONNECTIONS`], or fewer
/// when the process's descriptor limit (`ulimit -n`) minus
/// [`limits::RESERVED_DESCRIPTORS`] is lower.
pub fn connection_limit() -> usize {
    #[cfg(unix)]
    let descriptors = rustix::process::getrlimit(rustix::process::Resource::Nofile)
        .current
        .and_then(|limit| usize::try_from(limit).ok())
        .unwrap_or(usize::MAX);
    #[cfg(not(unix))]
    let descriptors = usize::MAX;
    limits::MAX_CONNECTIONS
        .min(descriptors.saturating_sub(limits::RESERVED_DESCRIPTORS))
        .max(8)
}
