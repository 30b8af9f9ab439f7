//! What every report page shares: the page around a report's body, its
//! style (inline: a report is read without a network), and how a number
//! is shown.

use maud::{DOCTYPE, Markup, PreEscaped, html};

const STYLE: &str = "body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;max-width:980px;margin:2rem auto;\
padding:0 1rem;color:#1d2630;line-height:1.45}h1{margin-bottom:.2rem}h2{margin-top:2rem;border-bottom:1px solid #d8dee6;\
padding-bottom:.2rem}table{border-collapse:collapse;margin:.6rem 0;font-size:.92rem}td,th{border:1px solid #d8dee6;\
padding:.25rem .6rem;text-align:right}th{background:#f2f5f8}td:first-child,th:first-child{text-align:left}\
.muted{color:#5b6775}.verdict{padding:.6rem .9rem;border-radius:4px;border:1px solid}.verdict.ok{background:#e8f3ec;border-color:#1a7f37}.verdict.bad{background:#fbeeee;border-color:#b42318}.ok{color:#1a7f37}.bad{color:#b42318}code{background:#f2f5f8;padding:.1rem .3rem;border-radius:3px}\
.warn{background:#fff6e5;border:1px solid #f0c36d;padding:.5rem .8rem;border-radius:4px}.id{background:#e8f3ec}\
.n{background:#fbeeee}.z{background:#f2f2f2}svg{max-width:100%;height:auto}";

/// A whole report page: `title` in the browser's tab, gecaro's style, and
/// `body`; the text written to the file (with its final line break).
pub(crate) fn page(title: &str, body: Markup) -> String {
    html! {
        (DOCTYPE)
        html lang="en" {
            head {
                meta charset="utf-8";
                title { (title) }
                style { (PreEscaped(STYLE)) }
            }
            body { (body) }
        }
    }
    .into_string()
        + "\n"
}

/// A number as a report shows it: at most six decimals between 10⁻³ and
/// 10⁴ (trailing zeros dropped), else in scientific notation.
pub(crate) fn number(value: f64) -> String {
    if value == 0.0 {
        "0".into()
    } else if value.abs() >= 1e-3 && value.abs() < 1e4 {
        let text = format!("{value:.6}");
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        format!("{value:.3e}")
    }
}
