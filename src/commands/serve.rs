//! `gecaro serve`: the web page, until Ctrl-C.

use crate::cli::ServeArgs;
use crate::failure::Failure;

pub(crate) fn serve(args: &ServeArgs) -> Result<(), Failure> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|error| Failure::numerical(format!("cannot start the server: {error}")))?;
    let served = runtime.block_on(async {
        let server = gecaro_web::Server::bind(&gecaro_web::Config {
            folder: args.dir.clone(),
            port: args.port,
        })
        .await
        .map_err(|error| Failure::input(error.to_string()))?;
        println!(
            "gecaro {} serving {} at {} — listening on 127.0.0.1 only; Ctrl-C stops it",
            env!("CARGO_PKG_VERSION"),
            server.folder().display(),
            server.url()
        );
        if args.open
            && let Err(error) = open::that_detached(server.url())
        {
            eprintln!(
                "warning: cannot open a browser ({error}); open {} yourself",
                server.url()
            );
        }
        server
            .run(async {
                stop_signal().await;
                eprintln!(
                    "stopping: the requests under way finish (a few seconds); jobs still \
                     computing are abandoned; Ctrl-C again stops at once"
                );
                // A second signal stops at once.
                tokio::spawn(async {
                    stop_signal().await;
                    gecaro_io::remove_temporary_files();
                    std::process::exit(130);
                });
            })
            .await
            .map_err(|error| Failure::numerical(error.to_string()))
    });
    // Jobs computing on blocking threads are abandoned rather than waited
    // for (an identification can run for minutes); their half-written
    // outputs are removed, and no new one starts.
    runtime.shutdown_timeout(std::time::Duration::from_millis(200));
    gecaro_io::remove_temporary_files();
    served
}

/// Ctrl-C, or SIGTERM or SIGHUP (a service manager's stop, a closed
/// terminal).
async fn stop_signal() {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{SignalKind, signal};
        let (Ok(mut terminate), Ok(mut hangup)) = (
            signal(SignalKind::terminate()),
            signal(SignalKind::hangup()),
        ) else {
            let _ = tokio::signal::ctrl_c().await;
            return;
        };
        tokio::select! {
            _ = tokio::signal::ctrl_c() => {}
            _ = terminate.recv() => {}
            _ = hangup.recv() => {}
        }
    }
    #[cfg(not(unix))]
    {
        let _ = tokio::signal::ctrl_c().await;
    }
}
