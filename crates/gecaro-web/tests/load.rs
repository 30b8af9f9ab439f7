//! A bounded load test: 2,000 requests from 16 concurrent local clients to a
//! real server over TCP, a mix of the page's reads and of the table checks and
//! poses it sends while a robot is edited. Every one must succeed. (Speed is
//! measured in docs/performance.md, not asserted here.)

use std::sync::Arc;

use bytes::Bytes;
use http_body_util::{BodyExt, Full};
use hyper_util::client::legacy::Client;
use hyper_util::rt::TokioExecutor;
use serde_json::{Value, json};

const REQUESTS: usize = 2_000;
const CLIENTS: usize = 16;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_thousand_requests_all_succeed() {
    let folder = tempfile::tempdir().expect("folder");
    let server = gecaro_web::Server::bind(&gecaro_web::Config {
        folder: folder.path().to_owned(),
        port: 0,
    })
    .await
    .expect("server");
    let base = server.url().trim_end_matches('/').to_owned();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let serving = tokio::spawn(server.run(async {
        let _ = stopped.await;
    }));

    let client: Client<_, Full<Bytes>> = Client::builder(TokioExecutor::new()).build_http();
    let get = |path: &str| {
        hyper::Request::get(format!("{base}{path}"))
            .body(Full::new(Bytes::new()))
            .expect("request")
    };
    let response = client
        .request(get("/api/robots/ready/stanford"))
        .await
        .expect("answer");
    let view: Value = serde_json::from_slice(
        &response
            .into_body()
            .collect()
            .await
            .expect("body")
            .to_bytes(),
    )
    .expect("JSON");
    let robot = view["document"].clone();
    let bodies = Arc::new([
        json!({ "robot": robot }).to_string(),
        json!({ "robot": robot, "q": [0.3, -0.2, 0.5, 0.1, 0.9, -0.4] }).to_string(),
    ]);

    let mut clients = Vec::new();
    for worker in 0..CLIENTS {
        let client = client.clone();
        let base = base.clone();
        let bodies = Arc::clone(&bodies);
        clients.push(tokio::spawn(async move {
            let mut failures = Vec::new();
            for index in (worker..REQUESTS).step_by(CLIENTS) {
                let request = match index % 4 {
                    0 => hyper::Request::get(format!("{base}/api/info"))
                        .body(Full::new(Bytes::new())),
                    1 => hyper::Request::get(format!("{base}/api/robots/ready/puma560"))
                        .body(Full::new(Bytes::new())),
                    2 => hyper::Request::post(format!("{base}/api/robots/check"))
                        .header("content-type", "application/json")
                        .body(Full::new(Bytes::from(bodies[0].clone()))),
                    _ => hyper::Request::post(format!("{base}/api/robots/pose"))
                        .header("content-type", "application/json")
                        .body(Full::new(Bytes::from(bodies[1].clone()))),
                }
                .expect("request");
                match client.request(request).await {
                    Ok(response) if response.status().is_success() => {
                        let _ = response.into_body().collect().await;
                    }
                    Ok(response) => {
                        failures.push(format!("request {index}: {}", response.status()))
                    }
                    Err(error) => failures.push(format!("request {index}: {error}")),
                }
            }
            failures
        }));
    }
    let mut failures = Vec::new();
    for worker in clients {
        failures.extend(worker.await.expect("client task"));
    }
    assert!(
        failures.is_empty(),
        "{} of {REQUESTS} failed: {failures:?}",
        failures.len()
    );
    let _ = stop.send(());
    serving.await.expect("server task").expect("server");
}

/// Sockets held open without a request, and requests whose headers never
/// finish, are closed after the header timeout; while more of them than the
/// server takes at once are held, a normal request is still answered.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn idle_and_slow_connections_are_closed_and_a_client_is_still_served() {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let folder = tempfile::tempdir().expect("folder");
    let server = gecaro_web::Server::bind(&gecaro_web::Config {
        folder: folder.path().to_owned(),
        port: 0,
    })
    .await
    .expect("server")
    .with_connection_bounds(16, std::time::Duration::from_millis(500));
    let url = server.url().trim_end_matches('/').to_owned();
    let address = url.trim_start_matches("http://").to_owned();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let serving = tokio::spawn(server.run(async {
        let _ = stopped.await;
    }));
    // 40 idle sockets and 10 with half-sent headers: more than the 16 taken at once.
    let mut held = Vec::new();
    for index in 0..50 {
        let mut socket = tokio::net::TcpStream::connect(&address)
            .await
            .expect("connect");
        if index % 5 == 0 {
            socket
                .write_all(b"GET /api/info HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
                .await
                .expect("send");
        }
        held.push(socket);
    }
    // A normal client is answered once the held sockets time out.
    let client: Client<_, Full<Bytes>> = Client::builder(TokioExecutor::new()).build_http();
    let request = hyper::Request::get(format!("{url}/api/info"))
        .body(Full::new(Bytes::new()))
        .expect("request");
    let response =
        tokio::time::timeout(std::time::Duration::from_secs(20), client.request(request))
            .await
            .expect("answered within 20 s")
            .expect("answer");
    assert!(response.status().is_success());
    // Every held socket has been closed by the server (end of stream, or a
    // reset), none is left hanging.
    for (index, mut socket) in held.into_iter().enumerate() {
        let mut buffer = [0u8; 512];
        let read = tokio::time::timeout(std::time::Duration::from_secs(20), async {
            loop {
                match socket.read(&mut buffer).await {
                    Ok(0) | Err(_) => break,
                    Ok(_) => {}
                }
            }
        })
        .await;
        assert!(read.is_ok(), "socket {index} is still open after 20 s");
    }
    let _ = stop.send(());
    serving.await.expect("server task").expect("server");
}
