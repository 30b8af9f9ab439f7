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

use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::routing::get;

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
        .route("/app.js", get(page::script))
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
        })
    }

    /// The page's address.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// The folder served.
    pub fn folder(&self) -> &std::path::Path {
        self.state.workspace().root()
    }

    /// Serves until `shutdown` completes.
    ///
    /// # Errors
    /// [`Error::Serve`] when the listener fails.
    pub async fn run(
        self,
        shutdown: impl Future<Output = ()> + Send + 'static,
    ) -> Result<(), Error> {
        axum::serve(self.listener, router(self.state))
            .with_graceful_shutdown(shutdown)
            .await
            .map_err(Error::Serve)
    }
}
