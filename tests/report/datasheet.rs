//! `sinedec datasheet`: the page of the embedded default (`--quick`, the CI grid) rendered in
//! headless Chromium: every figure loads with a non-empty box, no script or console error,
//! and every number of the tables equals the one `datasheet.json` holds; the latency equals
//! the one `sinedec check` prints, and the measured errors sit where the decoder's design
//! puts them. A `[capacitive]` config is refused with nothing written.
//!
//! Chromium is a tool like Yosys: the test fails with the install command when it is
//! missing (`scripts/test.sh` installs it).
use crate::common;
use serde_json::Value;
use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");
const INSTALL: &str = "apt-get install -y chromium chromium-driver (scripts/test.sh does this)";

/// The Chromium binary, or a panic with the install hint.
fn chromium() -> &'static str {
    let ok = Command::new("chromium").arg("--version").output();
    assert!(
        ok.is_ok_and(|o| o.status.success()),
        "chromium not found; install it: {INSTALL}"
    );
    "chromium"
}

/// The DOM of `page` after its scripts ran, as headless Chromium serializes it.
fn dump_dom(page: &Path, profile: &Path) -> String {
    let out = Command::new(chromium())
        .args([
            "--headless",
            "--disable-gpu",
            "--no-sandbox",
            "--no-first-run",
            "--virtual-time-budget=5000",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--dump-dom")
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("chromium runs");
    assert!(
        out.status.success(),
        "chromium failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8 DOM")
}

fn unescape(s: &str) -> String {
    s.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&amp;", "&")
}

/// The text of the element `<pre id="selfcheck">` of `dom`.
fn selfcheck(dom: &str) -> Value {
    let start = dom
        .rfind("<pre id=\"selfcheck\">")
        .expect("#selfcheck in the page")
        + 20;
    let end = start + dom[start..].find("</pre>").expect("#selfcheck closed");
    let text = unescape(&dom[start..end]);
    serde_json::from_str(&text)
        .unwrap_or_else(|e| panic!("the self-check did not run ({e}): {text:?}"))
}

/// Every `data-key="K">TEXT<` of `dom`: (K, TEXT).
fn keyed_numbers(dom: &str) -> Vec<(String, String)> {
    let mut v = vec![];
    let mut rest = dom;
    while let Some(i) = rest.find("data-key=\"") {
        rest = &rest[i + 10..];
        let k = &rest[..rest.find('"').expect("closing quote")];
        let gt = rest.find('>').expect("tag end") + 1;
        let text = &rest[gt..gt + rest[gt..].find('<').expect("element end")];
        v.push((k.to_string(), text.trim().to_string()));
    }
    v
}

/// `sinedec check`'s `latency CONV -> position` cycles for the default.
fn check_latency() -> u64 {
    let out = Command::new(BIN)
        .arg("check")
        .output()
        .expect("sinedec check");
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find(|l| l.starts_with("latency CONV -> position"))
        .expect("check prints the latency");
    line["latency CONV -> position".len()..]
        .split_whitespace()
        .next()
        .and_then(|w| w.parse().ok())
        .expect("a cycle count")
}

#[test]
fn the_default_page_renders_in_chromium_and_matches_its_json() {
    let browser = chromium();
    let dir = common::workdir("datasheet_default");
    let out = dir.join("ds");
    let run = Command::new(BIN)
        .args(["datasheet", "--quick", "-o"])
        .arg(&out)
        .output()
        .expect("sinedec datasheet runs");
    assert!(
        run.status.success(),
        "sinedec datasheet failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("datasheet.json")).expect("JSON"))
            .expect("valid JSON");
    let html = std::fs::read_to_string(out.join("index.html")).expect("index.html");
    // Self-contained: nothing is fetched.
    for bad in ["src=\"http", "href=\"http", "<link", "src=\"//", "@import"] {
        assert!(
            !html.contains(bad),
            "the page refers to an external asset: {bad}"
        );
    }
    let dom = dump_dom(
        &out.join("index.html").canonicalize().expect("path"),
        &dir.join(browser),
    );
    let check = selfcheck(&dom);
    assert_eq!(
        check["errors"],
        Value::Array(vec![]),
        "errors in the page: {check}"
    );
    let figures = check["figures"].as_array().expect("figures");
    let ids: Vec<&str> = figures.iter().filter_map(|f| f["id"].as_str()).collect();
    // The figures for a config with static correction and no velocity estimator.
    for want in ["fig-angle", "fig-histogram", "fig-speed", "fig-lissajous"] {
        assert!(ids.contains(&want), "figure {want} missing: {ids:?}");
    }
    for f in figures {
        let (w, h) = (
            f["width"].as_f64().unwrap_or(0.0),
            f["height"].as_f64().unwrap_or(0.0),
        );
        assert!(
            w > 100.0 && h > 100.0 && f["loaded"] == true,
            "figure not drawn: {f}"
        );
    }
    // The tables' numbers are the JSON's, to the digits printed.
    let cells = keyed_numbers(&dom);
    assert!(
        cells.len() >= 40,
        "only {} numbers in the tables",
        cells.len()
    );
    for (k, text) in &cells {
        let want = json
            .pointer(k)
            .and_then(Value::as_f64)
            .unwrap_or_else(|| panic!("{k}: not in datasheet.json"));
        let got: f64 = text
            .parse()
            .unwrap_or_else(|_| panic!("{k}: `{text}` is not a number"));
        let decimals = text.split_once('.').map_or(0, |(_, d)| d.len());
        let half_unit = 0.5 * 10f64.powi(-(decimals as i32)) * (1.0 + 1e-9);
        assert!(
            (got - want).abs() <= half_unit,
            "{k}: page {text}, JSON {want}"
        );
    }
    let sweep = json["sweep"].as_array().expect("sweep");
    for i in 0..json["accuracy"].as_array().map_or(0, Vec::len) {
        assert!(cells
            .iter()
            .any(|(k, _)| k == &format!("/accuracy/{i}/max_lsb")));
    }
    assert!(cells
        .iter()
        .any(|(k, _)| k == &format!("/sweep/{}/max_lsb", sweep.len() - 1)));
    // The latency is `check`'s.
    assert_eq!(json["latency"][0]["cycles"].as_u64(), Some(check_latency()));
    // Below the unwrap limit an ideal encoder is decoded within the error budget of the
    // design: the 14-bit codes at 80 % of full scale (6554 codes of amplitude; one code is
    // at most 2^14 / (pi / 2) / 6554 = 1.6 LSB of angle), the CORDIC's residual (0.26 LSB at
    // N = 14) and the rounding: under 4 LSB. The imperfections (1 % offsets and gain
    // mismatch, 0.5 degree, 0.5 % third harmonic) are not corrected by the default's static
    // zero correction: each costs about 0.005..0.01 rad = 50..100 LSB, together some hundreds.
    let limit = json["overview"]["unwrap_limit_rpm"]
        .as_f64()
        .expect("limit");
    for r in sweep
        .iter()
        .filter(|r| r["rpm"].as_f64().is_some_and(|v| v > 0.0 && v < limit))
    {
        let ideal = r["ideal_max_lsb"].as_f64().expect("ideal");
        let imperfect = r["max_lsb"].as_f64().expect("imperfect");
        assert!(ideal < 4.0, "ideal encoder at {}: {ideal} LSB", r["rpm"]);
        assert!(
            imperfect > 50.0 && imperfect < 1000.0,
            "imperfect at {}: {imperfect}",
            r["rpm"]
        );
    }
}

#[test]
fn a_capacitive_config_is_refused_with_nothing_written() {
    let dir = common::workdir("datasheet_capacitive");
    let cfg = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/cyclone3_capacitive.toml");
    let out = dir.join("ds");
    let run = Command::new(BIN)
        .args(["datasheet", "--quick", "-o"])
        .arg(&out)
        .arg(&cfg)
        .output()
        .expect("sinedec datasheet runs");
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(
        err.contains("[capacitive]") && err.contains("sinedec simulate"),
        "{err}"
    );
    assert!(!out.exists(), "the output directory was created");
}
