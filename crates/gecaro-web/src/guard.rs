//! What keeps a local server local: requests must be addressed to the
//! server's own host name, in one `Host` header (any letter case) (a page of another site that rebinds a DNS name to
//! 127.0.0.1 is refused), state-changing requests from another origin are
//! refused (no cross-site saves into the folder), and every answer carries
//! headers that keep browsers from sniffing, framing or leaking it. A request
//! that takes longer than [`crate::limits::REQUEST_TIMEOUT`] (an oversized
//! computation), or whose body stops arriving
//! ([`crate::limits::BODY_TIMEOUT`]), is answered 408 and its connection
//! freed.

use axum::extract::{Request, State};
use axum::http::{HeaderValue, Method, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use crate::error::ApiError;
use crate::state::AppState;

const CONTENT_SECURITY_POLICY: &str = "default-src 'self'; img-src 'self' data: blob:; \
     style-src 'self' 'unsafe-inline'; script-src 'self'; connect-src 'self'; \
     frame-ancestors 'none'; base-uri 'none'; form-action 'none'";

/// The middleware (see the module docs).
pub(crate) async fn guard(State(state): State<AppState>, request: Request, next: Next) -> Response {
    let allowed = state.allowed_hosts();
    if !allowed.is_empty() {
        let mut hosts = request.headers().get_all(header::HOST).iter();
        let (first, second) = (hosts.next(), hosts.next());
        if second.is_some() {
            return ApiError::BadRequest(
                "a request carries one Host header; this one has several".into(),
            )
            .into_response();
        }
        let host = first.and_then(|value| value.to_str().ok()).unwrap_or("");
        // Host names are case-insensitive (RFC 9110 §4.2.3).
        if !allowed.iter().any(|name| name.eq_ignore_ascii_case(host)) {
            return ApiError::Forbidden(format!(
                "this server answers requests addressed to {}, not {host:?}",
                allowed.join(" or ")
            ))
            .into_response();
        }
        let changes_state = !matches!(*request.method(), Method::GET | Method::HEAD);
        let mut origins = request.headers().get_all(header::ORIGIN).iter();
        let (first, second) = (origins.next(), origins.next());
        if changes_state && second.is_some() {
            return ApiError::BadRequest(
                "a request carries at most one Origin header; this one has several".into(),
            )
            .into_response();
        }
        if changes_state && let Some(origin) = first {
            let origin = origin.to_str().unwrap_or("");
            let same = allowed.iter().any(|name| {
                origin
                    .get(..7)
                    .is_some_and(|scheme| scheme.eq_ignore_ascii_case("http://"))
                    && origin[7..].eq_ignore_ascii_case(name)
            });
            if !same {
                return ApiError::Forbidden(format!(
                    "requests from the page {origin:?} are refused; use the page this server serves"
                ))
                .into_response();
            }
        }
    }
    let limit = state.request_timeout();
    let answer = async {
        match whole_body(request).await {
            Ok(request) => next.run(request).await,
            Err(response) => *response,
        }
    };
    let Ok(mut response) = tokio::time::timeout(limit, answer).await else {
        return ApiError::Timeout(format!(
            "the request took longer than {:.1} s and was abandoned; ask for less (fewer \
             configurations), or use an identification job",
            limit.as_secs_f64()
        ))
        .into_response();
    };
    let headers = response.headers_mut();
    headers.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    headers.insert(header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY"));
    headers.insert(
        header::REFERRER_POLICY,
        HeaderValue::from_static("no-referrer"),
    );
    headers.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(CONTENT_SECURITY_POLICY),
    );
    headers
        .entry(header::CACHE_CONTROL)
        .or_insert(HeaderValue::from_static("no-store"));
    response
}

/// The request with its body read whole within [`crate::limits::BODY_TIMEOUT`]
/// (and a second per MB declared), or the answer: 408 for a body that stops
/// arriving, 413 for one beyond [`crate::limits::MAX_BODY_BYTES`].
async fn whole_body(request: Request) -> Result<Request, Box<Response>> {
    if matches!(*request.method(), Method::GET | Method::HEAD) {
        return Ok(request);
    }
    let declared_mb = request
        .headers()
        .get(header::CONTENT_LENGTH)
        .and_then(|value| value.to_str().ok())
        .and_then(|value| value.parse::<u64>().ok())
        .unwrap_or(0)
        .div_ceil(1 << 20);
    let limit = crate::limits::BODY_TIMEOUT
        + std::time::Duration::from_secs(
            declared_mb.min(crate::limits::MAX_BODY_BYTES as u64 >> 20),
        );
    let (parts, body) = request.into_parts();
    match tokio::time::timeout(
        limit,
        axum::body::to_bytes(body, crate::limits::MAX_BODY_BYTES),
    )
    .await
    {
        Ok(Ok(bytes)) => Ok(Request::from_parts(parts, axum::body::Body::from(bytes))),
        Ok(Err(_)) => Err(Box::new(
            ApiError::TooLarge(format!(
                "the request's body is larger than {} MB, or broke off",
                crate::limits::MAX_BODY_BYTES >> 20
            ))
            .into_response(),
        )),
        Err(_) => Err(Box::new(
            ApiError::Timeout(format!(
                "the request's body stopped arriving (not whole within {:.0} s of its headers)",
                limit.as_secs_f64()
            ))
            .into_response(),
        )),
    }
}
