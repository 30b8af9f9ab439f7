//! The page in a real headless Chromium, driven as a person would use it:
//! open the Stanford arm, compute the identifiable parameters of Position
//! measure (31), generate data and identify them (convergence plot and
//! parameter table appear), save the calibrated robot, and type an invalid
//! value into the table (a validation message appears).
//!
//! Needs Debian's `chromium` and `chromium-driver` (installed by `.ci/run`).
//! Without them the test says so and passes, unless `GECARO_REQUIRE_E2E=1`
//! (set by CI), where their absence is a failure. Screenshots go to
//! `target/screenshots/`.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use fantoccini::{Client, ClientBuilder, Locator, key::Key};
use serde_json::json;

/// The browser and its driver, if installed.
fn browser() -> Option<(PathBuf, PathBuf)> {
    let find = |variable: &str, candidates: &[&str]| -> Option<PathBuf> {
        if let Ok(path) = std::env::var(variable) {
            return Some(PathBuf::from(path));
        }
        candidates
            .iter()
            .map(PathBuf::from)
            .find(|path| path.is_file())
    };
    let chromium = find(
        "GECARO_CHROMIUM",
        &[
            "/usr/bin/chromium",
            "/usr/bin/chromium-browser",
            "/usr/bin/google-chrome",
        ],
    )?;
    let driver = find(
        "GECARO_CHROMEDRIVER",
        &["/usr/bin/chromedriver", "/usr/lib/chromium/chromedriver"],
    )?;
    Some((chromium, driver))
}

/// chromedriver, stopped when dropped.
struct Driver(Child);

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|listener| listener.local_addr())
        .map(|address| address.port())
        .expect("a free port")
}

fn screenshots() -> PathBuf {
    let target = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("target/tmp is inside target")
        .join("screenshots");
    std::fs::create_dir_all(&target).expect("screenshot folder");
    target
}

async fn screenshot(client: &Client, name: &str) {
    let png = client.screenshot().await.expect("screenshot");
    std::fs::write(screenshots().join(name), png).expect("write screenshot");
}

async fn click(client: &Client, selector: &str) {
    client
        .wait()
        .at_most(Duration::from_secs(20))
        .for_element(Locator::Css(selector))
        .await
        .unwrap_or_else(|error| panic!("{selector}: {error}"))
        .click()
        .await
        .unwrap_or_else(|error| panic!("click {selector}: {error}"));
}

/// The text of `selector` once it exists and is not empty.
async fn text_of(client: &Client, selector: &str, seconds: u64) -> String {
    text_when(client, selector, seconds, |_| true).await
}

/// The text of `selector` once it exists, is not empty and satisfies `ready`.
async fn text_when(
    client: &Client,
    selector: &str,
    seconds: u64,
    ready: impl Fn(&str) -> bool,
) -> String {
    let deadline = std::time::Instant::now() + Duration::from_secs(seconds);
    let mut last = String::new();
    loop {
        if let Ok(element) = client.find(Locator::Css(selector)).await
            && let Ok(text) = element.text().await
        {
            if !text.trim().is_empty() && ready(&text) {
                return text;
            }
            last = text;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "{selector} did not show the expected text within {seconds} s (last: {last:?})"
        );
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

async fn count(client: &Client, selector: &str) -> usize {
    client
        .find_all(Locator::Css(selector))
        .await
        .expect("find")
        .len()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_page_works_as_a_person_uses_it() {
    let Some((chromium, chromedriver)) = browser() else {
        assert!(
            std::env::var("GECARO_REQUIRE_E2E").as_deref() != Ok("1"),
            "GECARO_REQUIRE_E2E=1 but chromium/chromedriver are not installed \
             (apt-get install chromium chromium-driver)"
        );
        eprintln!("skipped: chromium and chromedriver are not installed");
        return;
    };
    let folder = tempfile::tempdir().expect("folder");
    let server = gecaro_web::Server::bind(&gecaro_web::Config {
        folder: folder.path().to_owned(),
        port: 0,
    })
    .await
    .expect("server");
    let url = server.url().to_owned();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let serving = tokio::spawn(server.run(async {
        let _ = stopped.await;
    }));

    let port = free_port();
    let _driver = Driver(
        Command::new(&chromedriver)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts"),
    );
    let profile = tempfile::tempdir().expect("profile");
    let mut capabilities = serde_json::Map::new();
    capabilities.insert(
        "goog:chromeOptions".into(),
        json!({
            "binary": chromium,
            "args": [
                "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                "--disable-background-networking", "--disable-component-update", "--disable-sync",
                format!("--user-data-dir={}", profile.path().display()),
                "--window-size=1400,1900",
            ],
        }),
    );
    let mut client = None;
    for _ in 0..100 {
        match ClientBuilder::new(hyper_util::client::legacy::connect::HttpConnector::new())
            .capabilities(capabilities.clone())
            .connect(&format!("http://127.0.0.1:{port}"))
            .await
        {
            Ok(connected) => {
                client = Some(connected);
                break;
            }
            Err(_) => tokio::time::sleep(Duration::from_millis(100)).await,
        }
    }
    let client = client.expect("chromedriver answers within 10 s");

    client.goto(&url).await.expect("page");
    text_when(&client, "#robot-name", 30, |name| name == "Stanford").await;

    // Robot ▸ Open…: another ready robot, then the Stanford again.
    click(&client, "#robot-open").await;
    click(&client, "#open-ready-puma560").await;
    text_when(&client, "#robot-name", 10, |name| name.contains("PUMA")).await;
    click(&client, "#robot-open").await;
    click(&client, "#open-ready-stanford").await;
    text_when(&client, "#robot-name", 10, |name| name == "Stanford").await;
    assert!(
        text_of(&client, "#robot-status", 10)
            .await
            .starts_with("valid")
    );
    screenshot(&client, "01-stanford.png").await;

    // Position measure ▸ Identifiable parameters.
    click(&client, "#tab-position").await;
    click(&client, "#function-identifiable").await;
    click(&client, "#position-identifiable-run").await;
    assert_eq!(
        text_of(&client, "#position-identifiable-count", 60).await,
        "31"
    );
    assert_eq!(
        count(&client, "#position-identifiable-grid td.s-identifiable").await,
        31
    );
    screenshot(&client, "02-identifiable-position.png").await;
    let observability = text_of(&client, "#position-identifiable-result p.observability", 5).await;
    assert!(
        observability.contains("random configurations") && observability.contains("O5 "),
        "{observability}"
    );

    // Plan: D-optimal configurations and the curve.
    click(&client, "#function-plan").await;
    client
        .find(Locator::Css("#position-plan-curve"))
        .await
        .expect("curve field")
        .send_keys("12, 24, 48")
        .await
        .expect("type");
    click(&client, "#position-plan-run").await;
    assert_eq!(
        text_of(&client, "#position-plan-count-result", 60).await,
        "25"
    );
    assert_eq!(
        count(&client, "#position-plan-curve-table tbody tr").await,
        3
    );
    assert_eq!(count(&client, "#position-plan-curve-plot svg").await, 1);
    screenshot(&client, "03-plan.png").await;

    // Points generation, then identification of the generated data.
    click(&client, "#function-generate").await;
    click(&client, "#position-generate-run").await;
    assert_eq!(
        text_of(&client, "#position-generate-count-result", 60).await,
        "50"
    );
    screenshot(&client, "03-generation.png").await;
    // The Identification function now offers the data just generated first.
    let selected = client
        .execute(
            "return document.getElementById('position-identify-data').value",
            vec![],
        )
        .await
        .expect("script");
    assert_eq!(selected.as_str(), Some("generated"));
    click(&client, "#position-generate-identify").await;
    click(&client, "#position-identify-run").await;
    assert_eq!(
        text_of(&client, "#position-identify-status", 120).await,
        "Converged (σ not stated)"
    );
    let verdict = text_of(&client, "#position-identify-verdict", 5).await;
    assert!(
        verdict.starts_with("Verdict: converged after") && verdict.contains("no σ was stated"),
        "{verdict}"
    );
    assert_eq!(
        count(&client, "#position-identify-convergence svg").await,
        1
    );
    assert!(count(&client, "#position-identify-convergence svg circle").await >= 2);
    assert_eq!(
        count(&client, "#position-identify-parameters tbody tr").await,
        31
    );
    let observability = text_when(
        &client,
        "#position-identify-result p.observability",
        5,
        |text| text.contains("of the data"),
    )
    .await;
    assert!(observability.contains("O1 "), "{observability}");
    let first = text_of(&client, "#position-identify-parameters tbody tr td", 5).await;
    assert!(!first.is_empty());
    screenshot(&client, "04-identification.png").await;

    // Again with a robust loss, a prior and a 3-fold cross-validation.
    client
        .execute(
            "document.getElementById('position-identify-loss').value = 'tukey';\
             document.getElementById('position-identify-prior').value = '5mm,0.5deg,1%';\
             document.getElementById('position-identify-cv').value = '3';",
            vec![],
        )
        .await
        .expect("script");
    click(&client, "#position-identify-run").await;
    let validation = text_when(&client, "#position-identify-cv-result", 120, |text| {
        text.contains("3 folds")
    })
    .await;
    assert!(validation.contains("held-out RMS"), "{validation}");
    let robustness = text_of(&client, "#position-identify-robustness", 5).await;
    assert!(robustness.starts_with("Loss tukey"), "{robustness}");
    assert!(robustness.contains("prior 5.000 mm"), "{robustness}");
    assert_eq!(
        count(&client, "#position-identify-parameters thead th").await,
        6,
        "the prior σ column"
    );

    // Save the calibrated robot into the folder: a valid robot file.
    click(&client, "#position-identify-save").await;
    let name = client
        .wait()
        .for_element(Locator::Css("#save-name"))
        .await
        .expect("save dialog");
    name.clear().await.expect("clear");
    name.send_keys("calibrated.toml").await.expect("type");
    click(&client, "#dialog-ok").await;
    let saved = folder.path().join("calibrated.toml");
    for _ in 0..100 {
        if saved.exists() {
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let calibrated = gecaro_io::read_robot_file(&saved).expect("a valid robot file was saved");
    assert_eq!(calibrated.robot.name(), "Stanford (calibrated)");

    // Robot ▸ Open…: a URDF of the folder, converted into the table.
    std::fs::copy(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../tests/data/urdf/kuka_kr16_2.urdf"),
        folder.path().join("kr16.urdf"),
    )
    .expect("copy the URDF");
    click(&client, "#robot-open").await;
    let urdf = client
        .wait()
        .for_element(Locator::XPath(
            "//div[@id='open-imports']/button[text()='kr16.urdf']",
        ))
        .await
        .expect("the URDF is listed");
    urdf.click().await.expect("open it");
    text_when(&client, "#robot-name", 30, |name| name == "kuka_kr16_2").await;
    assert!(
        text_of(&client, "#robot-origin", 5)
            .await
            .contains("converted from kr16.urdf")
    );
    assert!(text_of(&client, "#notes li", 5).await.contains("folded"));
    screenshot(&client, "05-urdf-opened.png").await;
    // Save as… URDF: the original names come back in the folder.
    click(&client, "#robot-save-as").await;
    client
        .find(Locator::Css("#save-format"))
        .await
        .expect("format choice")
        .select_by_value("urdf")
        .await
        .expect("choose URDF");
    let name = client.find(Locator::Css("#save-name")).await.expect("name");
    assert!(
        name.prop("value")
            .await
            .expect("value")
            .unwrap_or_default()
            .ends_with(".urdf")
    );
    name.clear().await.expect("clear");
    name.send_keys("kr16-out.urdf").await.expect("type");
    click(&client, "#dialog-ok").await;
    let exported = folder.path().join("kr16-out.urdf");
    for _ in 0..100 {
        if exported.exists() {
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    // Wait for the page to finish the save (its dialog closes, a toast says so).
    text_when(&client, "#toast", 10, |text| {
        text.contains("Saved kr16-out.urdf")
    })
    .await;
    let text = std::fs::read_to_string(&exported).expect("a URDF was saved");
    assert!(
        text.contains("name=\"joint_a1\"") && text.contains("name=\"tool0\""),
        "{text}"
    );

    // An invalid value in the table: the cell is marked and the message shown.
    let sigma = client
        .find(Locator::Css(
            r#"#frames-table input[data-frame="2"][data-key="sigma"]"#,
        ))
        .await
        .expect("sigma cell of frame 2");
    sigma.clear().await.expect("clear");
    sigma
        .send_keys(&format!("7{}", Key::Tab))
        .await
        .expect("type");
    let message = text_of(&client, "#problems li", 30).await;
    assert!(
        message.contains("Frame 2, sigma") && message.contains("not a frame type"),
        "{message}"
    );
    let class = sigma
        .attr("class")
        .await
        .expect("class")
        .unwrap_or_default();
    assert!(class.contains("invalid"), "{class}");
    assert!(
        text_of(&client, "#robot-status", 5)
            .await
            .contains("problem")
    );
    let alpha = client
        .find(Locator::Css(
            r#"#frames-table input[data-frame="3"][data-key="alpha"]"#,
        ))
        .await
        .expect("alpha cell of frame 3");
    alpha.clear().await.expect("clear");
    alpha
        .send_keys(&format!("abc{}", Key::Tab))
        .await
        .expect("type");
    tokio::time::sleep(Duration::from_millis(400)).await;
    let all = client
        .find(Locator::Css("#problems"))
        .await
        .expect("problems")
        .text()
        .await
        .expect("text");
    assert!(
        all.contains("Frame 3, alpha: “abc” is not a number"),
        "{all}"
    );
    let disabled = client
        .find(Locator::Css("#position-identify-run"))
        .await
        .expect("run")
        .attr("disabled")
        .await
        .expect("attribute");
    assert!(
        disabled.is_some(),
        "runs are disabled while the table is invalid"
    );
    client
        .execute("window.scrollTo(0, 0)", Vec::new())
        .await
        .expect("scroll");
    screenshot(&client, "06-validation.png").await;

    client.close().await.expect("close the browser");
    let _ = stop.send(());
    serving.await.expect("server task").expect("server");
}
