//! What one request may ask for. The server runs on a person's machine; these
//! bounds keep any single request (a typo of 10⁹ configurations, a runaway
//! upload) from taking it over, and each is reported by name when exceeded.
//! The bounds of a job are the application layer's, the same on every front
//! end ([`gecaro_app::limits`]); these are the server's own.

pub use gecaro_app::limits::{
    MAX_CURVE_POINTS, MAX_FOLDS, MAX_GENERATE, MAX_ITERATIONS, MAX_RANDOM, MAX_TABLE_JOINTS,
};

/// Largest request body (a data file uploaded inline): 16 MiB.
pub const MAX_BODY_BYTES: usize = 16 << 20;
/// Largest data file read from the folder: 64 MiB.
pub const MAX_FILE_BYTES: u64 = 64 << 20;
/// Most configurations in one data set.
pub const MAX_SAMPLES: usize = 200_000;
/// Identification jobs kept for their results (the oldest a client has seen
/// finished go first; see `jobs::Jobs`).
pub const MAX_JOBS_KEPT: usize = 32;
/// Identification jobs queued or running at once.
pub const MAX_JOBS_ACTIVE: usize = 8;
/// Memory the queued and running identifications may need together
/// (`PreparedIdentification::memory_need`): a job that would pass it waits
/// for others to finish (503), one that needs more alone is refused (413),
/// rather than the server aborting on a failed allocation.
pub const MAX_JOBS_MEMORY: usize = 2 << 30;
/// Entries listed from the folder, per kind.
pub const MAX_LISTED: usize = 2_000;
/// The longest one request may take (identification jobs excepted).
pub const REQUEST_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(300);
/// The longest a connection may take to send a request's headers, and the
/// longest an idle (keep-alive) connection stays open: a browser reconnects
/// at once; a client that holds sockets without sending is let go.
pub const HEADER_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(5);
/// The longest a request's body may take to arrive after its headers: 5 s,
/// and one more per MB it declares (a local upload runs at hundreds of
/// MB/s). A client that sends part of a body and stops is answered 408 and
/// its connection freed, rather than holding a slot for the request timeout.
pub const BODY_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(5);
/// Most connections open at once, whatever the descriptor limit allows.
pub const MAX_CONNECTIONS: usize = 512;
/// Descriptors kept free of connections: for files, jobs and the listener.
pub const RESERVED_DESCRIPTORS: usize = 64;
/// Points sent for the 3D view, at most (a generation's measured points, a
/// plan's tool points).
pub const MAX_VIEW_POINTS: usize = 5_000;
