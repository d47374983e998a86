//! The data sheet's HTML page ([`html`] for the sinewave path, [`cap_html`] for the
//! capacitive one, sharing the head, tables and resources section): one file, its CSS
//! (`page.css`, with print rules: A4, no figure split across pages) and a small self-check
//! script (`selfcheck.js`: the size of every figure and every script or resource error,
//! written into `#selfcheck` for the browser test) inline, the figures as inline SVG. Every
//! number of a table carries `data-key`, the JSON pointer of the same number in
//! `datasheet.json`.
use super::capacitive::CapSheet;
use super::{Datasheet, Figure, Sheet};
use crate::config::Loaded;
use serde_json::Value;
use std::fmt::Write as _;

const CSS: &str = include_str!("page.css");
const SELFCHECK: &str = include_str!("selfcheck.js");

/// `s` with HTML's special characters escaped.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The page's tables read `sheet` through its JSON, by pointer: the numbers printed are
/// those of `datasheet.json` by construction, and the test checks it in the browser.
struct Cells {
    json: Value,
}

impl Cells {
    /// The value at `key` with `decimals` decimals in a `tag` element ("n/a" when absent).
    fn cell(&self, tag: &str, key: &str, decimals: usize) -> String {
        match self.json.pointer(key).and_then(Value::as_f64) {
            Some(v) => format!("<{tag} class=\"num\" data-key=\"{key}\">{v:.decimals$}</{tag}>"),
            None => format!("<{tag} class=\"num na\">n/a</{tag}>"),
        }
    }

    /// A number cell, see [`cell`](Self::cell).
    fn num(&self, key: &str, decimals: usize) -> String {
        self.cell("td", key, decimals)
    }

    /// A number in running text, see [`cell`](Self::cell).
    fn span(&self, key: &str, decimals: usize) -> String {
        self.cell("span", key, decimals)
    }
}

/// The rows of the JSON array `section` (`n` entries): one number cell per (field,
/// decimals).
fn keyed_rows(c: &Cells, section: &str, n: usize, fields: &[(&str, usize)]) -> Vec<String> {
    (0..n)
        .map(|i| {
            fields
                .iter()
                .map(|(f, d)| c.num(&format!("/{section}/{i}/{f}"), *d))
                .collect()
        })
        .collect()
}

/// A `<table>` with a header row.
fn table(head: &[&str], rows: &[String]) -> String {
    let mut t = String::from("<table><thead><tr>");
    for h in head {
        let _ = write!(t, "<th>{h}</th>");
    }
    t.push_str("</tr></thead><tbody>");
    for r in rows {
        let _ = write!(t, "<tr>{r}</tr>");
    }
    t.push_str("</tbody></table>\n");
    t
}

fn figure(n: &mut usize, f: &Figure) -> String {
    *n += 1;
    format!(
        "<figure id=\"{}\">{}<figcaption>Figure {}. {}</figcaption></figure>\n",
        f.id,
        f.svg.trim(),
        n,
        esc(&f.caption)
    )
}

/// The figures of `ds` whose id starts with `prefix`, numbered on from `n`.
fn figs_html(ds: &Datasheet, prefix: &str, n: &mut usize) -> String {
    ds.figures
        .iter()
        .filter(|f| f.id.starts_with(prefix))
        .map(|f| figure(n, f))
        .collect()
}

/// The document's head (title, self-check script, CSS) and the opening body tag.
fn head(top: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>{top}: data sheet</title>\n<script>{SELFCHECK}</script>\n<style>{CSS}</style></head><body>\n"
    )
}

/// The reproduce section and the end of the document.
fn tail(command: &str, generator: &str, name: &str, hash: &str, text: &str, h: usize) -> String {
    format!(
        "<h2>{h}. Reproduce</h2>\n<p>Command: <code>{}</code>. Generator: {}. Config {} (hash {}):</p>\n<pre class=\"config\">{}</pre>\n<pre id=\"selfcheck\"></pre>\n</body></html>\n",
        esc(command),
        esc(generator),
        esc(name),
        esc(hash),
        esc(text)
    )
}

/// The sinewave page of `ds`, whose tables are `s`.
pub fn html(loaded: &Loaded, ds: &Datasheet, s: &Sheet) -> String {
    let c = Cells {
        json: serde_json::to_value(s).unwrap_or(Value::Null),
    };
    let top = esc(&crate::emit::top_name(loaded));
    let mut n = 0;
    let figs_html = |prefix: &str, n: &mut usize| figs_html(ds, prefix, n);
    let mut b = head(&top);
    let _ = writeln!(
        b,
        "<header><h1>{top}</h1><p class=\"sub\">Sine/cosine encoder decoder, characterized in its closed loop. Config {} (hash {}); {}{}.</p></header>",
        esc(&s.config_name),
        esc(&s.config_hash),
        esc(&s.generator),
        if s.quick { "; reduced grid (--quick)" } else { "" }
    );
    b.push_str(&overview(&c, s));
    // 1. Accuracy.
    b.push_str("<h2>1. Accuracy</h2>\n<p>With the imperfections below (<code>sinedec simulate</code>'s options). Error = decoded position - true position at the sampling CONV, less its constant offset, in LSB of the position (2<sup>-F</sup> quadrant). Before correction: the angle of the raw ADC codes (atan2) against the true angle.</p>\n");
    b.push_str(&conditions(&c));
    let rows = keyed_rows(
        &c,
        "accuracy",
        s.accuracy.len(),
        &[
            ("rpm", 0),
            ("samples", 0),
            ("raw_max_lsb", 2),
            ("raw_rms_lsb", 2),
            ("max_lsb", 2),
            ("rms_lsb", 2),
        ],
    );
    b.push_str(&table(
        &[
            "speed (rpm)",
            "samples",
            "before: max (LSB)",
            "before: RMS (LSB)",
            "output: max (LSB)",
            "output: RMS (LSB)",
        ],
        &rows,
    ));
    b.push_str(&figs_html("fig-angle", &mut n));
    b.push_str(&figs_html("fig-histogram", &mut n));
    // 2. Speed.
    b.push_str("<h2>2. Error against speed</h2>\n");
    b.push_str(&figs_html("fig-speed", &mut n));
    let mut rows = keyed_rows(
        &c,
        "sweep",
        s.sweep.len(),
        &[
            ("rpm", 0),
            ("ideal_max_lsb", 2),
            ("ideal_rms_lsb", 2),
            ("max_lsb", 2),
            ("rms_lsb", 2),
        ],
    );
    for (r, x) in rows.iter_mut().zip(&s.sweep) {
        r.push_str(if x.above_limit {
            "<td>above</td>"
        } else {
            "<td></td>"
        });
    }
    b.push_str(&table(
        &[
            "speed (rpm)",
            "ideal: max (LSB)",
            "ideal: RMS (LSB)",
            "imperfect: max (LSB)",
            "imperfect: RMS (LSB)",
            "unwrap limit",
        ],
        &rows,
    ));
    // 3. Correction.
    b.push_str("<h2>3. Correction</h2>\n");
    b.push_str(&correction(&c, s));
    b.push_str(&figs_html("fig-lissajous", &mut n));
    b.push_str(&figs_html("fig-convergence", &mut n));
    // 4. Latency.
    b.push_str("<h2>4. Latency and sample rate</h2>\n");
    let rows: Vec<String> = s
        .latency
        .iter()
        .enumerate()
        .map(|(i, r)| {
            format!(
                "<td>{}</td>{}{}<td class=\"note\">{}</td>",
                esc(&r.output),
                c.num(&format!("/latency/{i}/cycles"), 0),
                c.num(&format!("/latency/{i}/ns"), 1),
                esc(&r.note)
            )
        })
        .collect();
    b.push_str(&table(&["output", "cycles", "ns", "counted"], &rows));
    let _ = writeln!(
        b,
        "<p>Sample rate {} samples/s per channel.</p>",
        c.span("/overview/sample_rate_sps", 0)
    );
    // 5. Velocity.
    b.push_str("<h2>5. Velocity</h2>\n");
    b.push_str(&velocity(&c, s));
    b.push_str(&figs_html("fig-velocity", &mut n));
    // 6. Resources.
    b.push_str("<h2>6. Resources and timing</h2>\n");
    b.push_str(&resources(&c, &s.resources));
    // 7. Reproduce.
    b.push_str(&tail(
        &s.command,
        &s.generator,
        &s.config_name,
        &s.config_hash,
        &s.config_text,
        7,
    ));
    b
}

/// The capacitive page of `ds`, whose tables are `s` (`super::capacitive`).
pub fn cap_html(loaded: &Loaded, ds: &Datasheet, s: &CapSheet) -> String {
    let c = Cells {
        json: serde_json::to_value(s).unwrap_or(Value::Null),
    };
    let top = esc(&crate::emit::top_name(loaded));
    let mut n = 0;
    let mut b = head(&top);
    let _ = writeln!(
        b,
        "<header><h1>{top}</h1><p class=\"sub\">Capacitive encoder decoder, characterized in its closed loop against the capacitive-encoder model. Config {} (hash {}); {}{}.</p></header>",
        esc(&s.config_name),
        esc(&s.config_hash),
        esc(&s.generator),
        if s.quick { "; reduced grid (--quick)" } else { "" }
    );
    let rows = number_rows(
        &c,
        "/overview",
        &[
            ("system clock (MHz)", "clock_mhz", 3),
            ("sample rate (samples/s, receiver)", "sample_rate_sps", 0),
            ("carrier (Hz)", "carrier_hz", 0),
            ("signal periods per turn", "periods_per_turn", 0),
            ("resolution (bits per turn)", "resolution_bits", 2),
            ("1 LSB (mechanical arc-seconds)", "lsb_arcsec", 4),
            (
                "speed limit (rpm; the low-pass corner)",
                "speed_limit_rpm",
                0,
            ),
            ("low-pass corner (Hz)", "lowpass_corner_hz", 0),
        ],
    );
    b.push_str(&table(&["key figure", "value"], &rows));
    let _ = writeln!(b, "<p class=\"note\">{}</p>", esc(&s.not_applicable));
    // 1. Accuracy.
    b.push_str("<h2>1. Accuracy</h2>\n<p>Error = decoded position - true mechanical position at par_valid, less its mean over the run (the filters' group delay is a constant lag at constant speed), in mechanical degrees and arc-seconds, as <code>sinedec simulate</code> prints it. Positions within the filters' settling window are not measured. Flagged: positions with <code>par_error</code> or <code>par_warning</code> set (the core's flags, or the filters' overflow and dropped-sample flags); they stay in the statistics. The runs with noise:</p>\n");
    let rows = number_rows(
        &c,
        "/conditions",
        &[
            (
                "<code>--amplitude (received, fraction of the ADC range)</code>",
                "amplitude",
                3,
            ),
            ("<code>--noise-lsb (RMS ADC LSB)</code>", "noise_lsb", 2),
            ("<code>--seed</code>", "seed", 0),
            ("settling window, not measured (ms)", "settle_ms", 2),
        ],
    );
    b.push_str(&table(&["condition", "value"], &rows));
    let rows = keyed_rows(
        &c,
        "accuracy",
        s.accuracy.len(),
        &[
            ("rpm", 0),
            ("samples", 0),
            ("max_deg", 5),
            ("rms_deg", 5),
            ("max_arcsec", 2),
            ("rms_arcsec", 2),
            ("flagged", 0),
        ],
    );
    b.push_str(&table(
        &[
            "speed (rpm)",
            "positions",
            "max (deg)",
            "RMS (deg)",
            "max (arc-s)",
            "RMS (arc-s)",
            "flagged",
        ],
        &rows,
    ));
    b.push_str(&figs_html(ds, "fig-angle", &mut n));
    b.push_str(&figs_html(ds, "fig-histogram", &mut n));
    // 2. Speed.
    b.push_str("<h2>2. Error against speed</h2>\n");
    b.push_str(&figs_html(ds, "fig-speed", &mut n));
    let rows = keyed_rows(
        &c,
        "sweep",
        s.sweep.len(),
        &[
            ("rpm", 0),
            ("ideal_max_deg", 5),
            ("ideal_rms_deg", 5),
            ("max_deg", 5),
            ("rms_deg", 5),
            ("flagged", 0),
        ],
    );
    b.push_str(&table(
        &[
            "speed (rpm)",
            "ideal: max (deg)",
            "ideal: RMS (deg)",
            "noise: max (deg)",
            "noise: RMS (deg)",
            "flagged",
        ],
        &rows,
    ));
    // 3. Processing.
    b.push_str("<h2>3. Processing time and sample rate</h2>\n<p>Per sample, from the derivation <code>sinedec check</code> and <code>sinedec simulate</code> print for this path.</p>\n");
    let rows: Vec<String> = s
        .processing
        .iter()
        .enumerate()
        .map(|(i, r)| {
            format!(
                "<td>{}</td>{}{}<td class=\"note\">{}</td>",
                esc(&r.stage),
                c.num(&format!("/processing/{i}/cycles"), 0),
                c.num(&format!("/processing/{i}/us"), 2),
                esc(&r.note)
            )
        })
        .collect();
    b.push_str(&table(&["stage", "cycles", "us", "counted"], &rows));
    let _ = writeln!(
        b,
        "<p>Sample rate {} samples/s (one receiver channel).</p>",
        c.span("/overview/sample_rate_sps", 0)
    );
    // 4. Resources.
    b.push_str("<h2>4. Resources and timing</h2>\n");
    b.push_str(&resources(&c, &s.resources));
    b.push_str(&tail(
        &s.command,
        &s.generator,
        &s.config_name,
        &s.config_hash,
        &s.config_text,
        5,
    ));
    b
}

/// Table rows "label | number" of the JSON values under `prefix`: (label, key, decimals).
fn number_rows(c: &Cells, prefix: &str, rows: &[(&str, &str, usize)]) -> Vec<String> {
    rows.iter()
        .map(|(l, k, d)| format!("<td>{l}</td>{}", c.num(&format!("{prefix}/{k}"), *d)))
        .collect()
}

fn overview(c: &Cells, s: &Sheet) -> String {
    let unwrap = if s.overview.qep_fallback {
        "unwrap limit (rpm; QEP fallback above)"
    } else {
        "unwrap limit (rpm; no QEP fallback)"
    };
    let rows = number_rows(
        c,
        "/overview",
        &[
            ("system clock (MHz)", "clock_mhz", 3),
            ("sample rate (samples/s per channel)", "sample_rate_sps", 0),
            ("resolution (bits per turn)", "resolution_bits", 2),
            ("1 LSB (mechanical arc-seconds)", "lsb_arcsec", 4),
            (unwrap, "unwrap_limit_rpm", 0),
        ],
    );
    table(&["key figure", "value"], &rows)
}

fn conditions(c: &Cells) -> String {
    let rows = number_rows(
        c,
        "/conditions",
        &[
            (
                "<code>--amplitude (fraction of the ADC range)</code>",
                "amplitude",
                3,
            ),
            ("<code>--noise-lsb (RMS ADC LSB)</code>", "noise_lsb", 2),
            (
                "<code>--offset-sin (fraction of the amplitude)</code>",
                "offset_sin",
                3,
            ),
            (
                "<code>--offset-cos (fraction of the amplitude)</code>",
                "offset_cos",
                3,
            ),
            ("<code>--gain-mismatch</code>", "gain_mismatch", 3),
            ("<code>--phase-error (deg)</code>", "phase_error_deg", 2),
            ("<code>--harmonic3</code>", "harmonic3", 3),
            ("<code>--seed</code>", "seed", 0),
        ],
    );
    table(&["imperfection", "value"], &rows)
}

fn correction(c: &Cells, s: &Sheet) -> String {
    let k = &s.correction;
    if k.automatic {
        format!(
            "<p>Automatic correction (<code>correction.mode = \"{}\"</code>): the coefficients in use against time, from the block's bit-exact model on the same samples.</p>{}",
            esc(&k.mode),
            table(
                &["coefficient updates", "last update (ms)"],
                &[format!("{}{}", c.num("/correction/updates", 0), c.num("/correction/last_update_ms", 3))]
            )
        )
    } else {
        format!(
            "<p>This config's correction is <code>correction.mode = \"{}\"</code>: fixed offsets and gains, so there is no convergence to show (<code>mode = \"auto\"</code> fits them at run time). The figure shows the samples before and after the fixed correction.</p>\n",
            esc(&k.mode)
        )
    }
}

fn velocity(c: &Cells, s: &Sheet) -> String {
    let Some(v) = &s.velocity else {
        return "<p>The velocity estimator is off in this config (<code>[velocity] enabled = false</code>).</p>\n".into();
    };
    let mut rows = vec![format!("<td>method</td><td>{}</td>", esc(&v.method))];
    rows.extend(number_rows(
        c,
        "/velocity",
        &[
            ("update rate (Hz)", "rate_hz", 1),
            ("1 LSB (rpm)", "lsb_rpm", 8),
            (
                "latency, tick to par_velocity_valid (cycles)",
                "latency_cycles",
                0,
            ),
            ("lag behind a ramp (update periods)", "lag_periods", 2),
            ("lag behind a ramp with the latency (ms)", "lag_ms", 3),
            (
                "measured lag on the ramp, against the encoder's speed at the strobe (ms)",
                "measured_lag_ms",
                3,
            ),
        ],
    ));
    table(&["velocity", "value"], &rows)
}

fn resources(c: &Cells, r: &super::resources::Resources) -> String {
    let mut o = String::new();
    if r.luts.is_some() {
        let rows = [format!(
            "<td>{}</td>{}{}{}{}<td>{}</td>",
            esc(&r.family),
            c.num("/resources/luts", 0),
            c.num("/resources/ffs", 0),
            c.num("/resources/brams", 0),
            c.num("/resources/multipliers", 0),
            esc(r.yosys.as_deref().unwrap_or(""))
        )];
        o.push_str(&table(
            &[
                "family",
                "LUTs",
                "FFs",
                "block RAMs",
                "multipliers",
                "synthesis",
            ],
            &rows,
        ));
    }
    if r.fmax_mhz.is_some() {
        let rows = [format!(
            "{}{}<td>{}</td><td>{}</td>",
            c.num("/resources/clock_mhz", 3),
            c.num("/resources/fmax_mhz", 2),
            r.seeds_mhz
                .iter()
                .enumerate()
                .map(|(i, _)| c.span(&format!("/resources/seeds_mhz/{i}"), 2))
                .collect::<Vec<_>>()
                .join(" / "),
            esc(r.rule.as_deref().unwrap_or(""))
        )];
        o.push_str(&table(
            &[
                "clock (MHz)",
                "ECP5-6 Fmax, median (MHz)",
                "seeds 1 / 2 / 3 (MHz)",
                "timing rule (docs/timing.md)",
            ],
            &rows,
        ));
    }
    for n in &r.notes {
        let _ = writeln!(o, "<p class=\"note\">{}</p>", esc(n));
    }
    o
}
