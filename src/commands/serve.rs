//! `gecaro serve`: the web page, until Ctrl-C.

use crate::cli::ServeArgs;
use crate::failure::Failure;

pub(crate) fn serve(args: &ServeArgs) -> Result<(), Failure> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|error| Failure::numerical(format!("cannot start the server: {error}")))?;
    runtime.block_on(async {
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
                let _ = tokio::signal::ctrl_c().await;
            })
            .await
            .map_err(|error| Failure::numerical(error.to_string()))
    })
}
