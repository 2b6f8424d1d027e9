//! The study's results: the CSV (one row per checkpoint), the derived figures (time to reach
//! each RMSE target, samples per second, farm speed-up), the one-line recommendation and the
//! self-contained HTML report (tables and the SVG figures inlined; the PNGs sit beside it).
//!
//! Data flow: [`RunResult`]s from `run` → [`summarise`] → CSV / `plots::Figures` / HTML.

use super::plots::{Figures, Line};
use super::run::Checkpoint;
use std::fmt::Write as _;
use std::path::Path;

/// One configuration's measurements.
pub struct RunResult {
    pub label: String,
    pub workers: Option<usize>,
    pub checkpoints: Vec<Checkpoint>,
    /// Why the run has no measurements, when it failed.
    pub failure: Option<String>,
}

impl RunResult {
    fn last(&self) -> Option<&Checkpoint> {
        self.checkpoints.last()
    }

    /// Samples per second over the whole run.
    pub fn rate(&self) -> Option<f64> {
        self.last()
            .filter(|c| c.seconds > 0.0)
            .map(|c| c.samples / c.seconds)
    }

    fn rmse_points(&self) -> Vec<(f64, f64)> {
        self.checkpoints
            .iter()
            .filter_map(|c| Some((c.seconds, c.error?.rmse)))
            .collect()
    }
}

/// Seconds for a run to reach `target` RMSE: interpolated on log–log axes between the last
/// checkpoint above the target and the first at or below it; None if never reached.
pub fn time_to(points: &[(f64, f64)], target: f64) -> Option<f64> {
    let i = points.iter().position(|p| p.1 <= target)?;
    let (t1, e1) = points[i];
    let Some(&(t0, e0)) = i.checked_sub(1).and_then(|j| points.get(j)) else {
        return Some(t1);
    };
    if !(e0 > e1 && e1 > 0.0 && t0 > 0.0 && t1 > 0.0) {
        return Some(t1);
    }
    let f = (e0.ln() - target.ln()) / (e0.ln() - e1.ln());
    Some((t0.ln() + f * (t1.ln() - t0.ln())).exp())
}

/// The default targets: the RMSE the first configuration (the scene as written) reached at
/// the end of its budget, and twice and √2 times that (what it reached at about a quarter
/// and half of it, as the error of an unbiased render falls as 1/√time).
pub fn default_targets(runs: &[RunResult]) -> Vec<f64> {
    let Some(base) = runs
        .iter()
        .find(|r| r.workers.is_none())
        .and_then(|r| r.last())
        .and_then(|c| c.error)
        .map(|e| e.rmse)
        .filter(|e| *e > 0.0)
    else {
        return Vec::new();
    };
    vec![2.0 * base, std::f64::consts::SQRT_2 * base, base]
}

/// The derived numbers of a study.
pub struct Summary {
    pub targets: Vec<f64>,
    /// Per local run (label, seconds to each target).
    pub to_target: Vec<(String, Vec<Option<f64>>)>,
    pub figures: Figures,
    pub recommendation: String,
}

pub fn summarise(runs: &[RunResult], targets: Vec<f64>) -> Summary {
    let local: Vec<&RunResult> = runs
        .iter()
        .filter(|r| r.workers.is_none() && r.failure.is_none())
        .collect();
    let to_target: Vec<(String, Vec<Option<f64>>)> = local
        .iter()
        .map(|r| {
            let pts = r.rmse_points();
            (
                r.label.clone(),
                targets.iter().map(|&t| time_to(&pts, t)).collect(),
            )
        })
        .collect();
    let lines = local
        .iter()
        .zip(&to_target)
        .map(|(r, (_, tt))| Line {
            label: r.label.clone(),
            rmse: r.rmse_points(),
            to_target: targets
                .iter()
                .zip(tt)
                .filter_map(|(&t, s)| Some((t, (*s)?)))
                .collect(),
        })
        .collect();
    let rates = runs
        .iter()
        .filter_map(|r| Some((r.label.clone(), r.rate()?)))
        .collect();
    let recommendation = recommend(&local, &targets, &to_target);
    Summary {
        targets,
        to_target,
        figures: Figures {
            lines,
            rates,
            speedup: speedup(runs),
        },
        recommendation,
    }
}

/// Farm speed-up: samples/s of each farm run over that of the 1-worker farm (or of the
/// smallest farm measured, scaled by its worker count).
fn speedup(runs: &[RunResult]) -> Vec<(usize, f64)> {
    let farms: Vec<(usize, f64)> = runs
        .iter()
        .filter_map(|r| Some((r.workers?, r.rate()?)))
        .collect();
    let Some(&(w0, r0)) = farms.iter().min_by_key(|f| f.0) else {
        return Vec::new();
    };
    let per_worker = r0 / w0 as f64;
    let mut out: Vec<(usize, f64)> = farms
        .iter()
        .map(|&(w, r)| {
            (
                w,
                if per_worker > 0.0 {
                    r / per_worker
                } else {
                    0.0
                },
            )
        })
        .collect();
    out.sort_by_key(|f| f.0);
    out
}

/// Which local configuration reaches the tightest target first; when none reaches it, the
/// one with the lowest final RMSE.
fn recommend(
    local: &[&RunResult],
    targets: &[f64],
    to_target: &[(String, Vec<Option<f64>>)],
) -> String {
    let tight = targets.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1));
    if let Some((k, &t)) = tight {
        let best = to_target
            .iter()
            .filter_map(|(l, tt)| Some((l, tt.get(k).copied().flatten()?)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((label, secs)) = best {
            return format!(
                "Recommendation: {label} reaches the target RMSE {t:.4} first, in {secs:.1} s of rendering."
            );
        }
    }
    let best = local
        .iter()
        .filter_map(|r| Some((&r.label, r.last()?.error?.rmse)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    match best {
        Some((label, e)) => format!(
            "Recommendation: {label} (no configuration reached the target; {label} ended lowest, RMSE {e:.4})."
        ),
        None => "Recommendation: none (no local configuration was measured).".to_string(),
    }
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(String::new, |v| format!("{v:.6e}"))
}

/// The CSV: one row per checkpoint of each run (farm runs: their one measurement).
pub fn write_csv(path: &Path, runs: &[RunResult]) -> std::io::Result<()> {
    let mut s = String::from(
        "config,workers,seconds,samples,spp,samples_per_second,rmse,rel_mse,failing_share\n",
    );
    for r in runs {
        for c in &r.checkpoints {
            let rate = (c.seconds > 0.0).then(|| c.samples / c.seconds);
            let _ = writeln!(
                s,
                "{},{},{:.6},{:.0},{:.4},{},{},{},{}",
                r.label,
                r.workers.map_or_else(String::new, |w| w.to_string()),
                c.seconds,
                c.samples,
                c.spp,
                opt(rate),
                opt(c.error.map(|e| e.rmse)),
                opt(c.error.map(|e| e.rel_mse)),
                opt(c.error.map(|e| e.failing)),
            );
        }
    }
    std::fs::write(path, s)
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// What the HTML report says beside the numbers.
pub struct Context<'a> {
    pub scene: &'a str,
    pub reference: &'a str,
    pub budget: f64,
    pub figure_note: Option<String>,
}

/// The self-contained HTML report.
pub fn html(ctx: &Context, runs: &[RunResult], sum: &Summary, svgs: &[(String, String)]) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>luxfarm study: {scene}</title>\n\
         <style>body{{font-family:sans-serif;margin:2em;max-width:1000px}}\
         table{{border-collapse:collapse}}td,th{{border:1px solid #aaa;padding:3px 8px;text-align:right}}\
         th{{background:#eee}}td:first-child{{text-align:left}}.rec{{font-size:1.2em;font-weight:bold}}</style>\n\
         </head><body>\n<h1>Speed against accuracy: {scene}</h1>\n\
         <p>Reference: {reference}. Budget: {budget:.1} s over all configurations. \
         Error in linear RGB against the reference; failing share = pixels failing Yee's \
         perceptual test against the reference.</p>\n<p class=\"rec\">{rec}</p>\n",
        scene = esc(ctx.scene),
        reference = esc(ctx.reference),
        budget = ctx.budget,
        rec = esc(&sum.recommendation),
    );
    h.push_str(
        "<h2>Final measurement per configuration</h2>\n<table><tr><th>configuration</th>\
        <th>render s</th><th>spp</th><th>samples/s</th><th>RMSE</th><th>relMSE</th>\
        <th>failing share</th></tr>\n",
    );
    for r in runs {
        match (r.last(), &r.failure) {
            (_, Some(f)) => {
                let _ = writeln!(
                    h,
                    "<tr><td>{}</td><td colspan=\"6\" style=\"text-align:left\">failed: {}</td></tr>",
                    esc(&r.label),
                    esc(f)
                );
            }
            (Some(c), None) => {
                let e = c.error;
                let _ = writeln!(
                    h,
                    "<tr><td>{}</td><td>{:.2}</td><td>{:.1}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                    esc(&r.label),
                    c.seconds,
                    c.spp,
                    opt(r.rate()),
                    opt(e.map(|e| e.rmse)),
                    opt(e.map(|e| e.rel_mse)),
                    opt(e.map(|e| e.failing)),
                );
            }
            (None, None) => {}
        }
    }
    h.push_str("</table>\n<h2>Render seconds to reach each RMSE target</h2>\n<table><tr><th>configuration</th>");
    for t in &sum.targets {
        let _ = write!(h, "<th>{t:.4}</th>");
    }
    h.push_str("</tr>\n");
    for (label, tt) in &sum.to_target {
        let _ = write!(h, "<tr><td>{}</td>", esc(label));
        for s in tt {
            let _ = write!(
                h,
                "<td>{}</td>",
                s.map_or_else(|| "not reached".into(), |s| format!("{s:.2}"))
            );
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</table>\n");
    if !sum.figures.speedup.is_empty() {
        h.push_str("<h2>Farm speed-up</h2>\n<table><tr><th>workers</th><th>speed-up</th></tr>\n");
        for (w, s) in &sum.figures.speedup {
            let _ = writeln!(h, "<tr><td>{w}</td><td>{s:.3}</td></tr>");
        }
        h.push_str("</table>\n");
    }
    h.push_str("<h2>Figures</h2>\n");
    if let Some(n) = &ctx.figure_note {
        let _ = writeln!(h, "<p>No figures: {}</p>", esc(n));
    }
    for (name, svg) in svgs {
        let _ = writeln!(
            h,
            "<figure id=\"{name}\">{}<figcaption>{name}.svg / {name}.png</figcaption></figure>",
            strip_xml_declaration(svg)
        );
    }
    h.push_str("<p>Data: study.csv (one row per checkpoint).</p>\n</body></html>\n");
    h
}

fn strip_xml_declaration(svg: &str) -> &str {
    match svg.strip_prefix("<?xml") {
        Some(rest) => rest.split_once("?>").map_or(svg, |(_, r)| r.trim_start()),
        None => svg,
    }
}

#[cfg(test)]
mod tests {
    use super::super::measure::Error;
    use super::*;

    fn run(label: &str, pts: &[(f64, f64)]) -> RunResult {
        RunResult {
            label: label.into(),
            workers: None,
            checkpoints: pts
                .iter()
                .map(|&(s, e)| Checkpoint {
                    seconds: s,
                    samples: 1000.0 * s,
                    spp: s,
                    error: Some(Error {
                        rmse: e,
                        rel_mse: e * e,
                        failing: 0.5,
                    }),
                })
                .collect(),
            failure: None,
        }
    }

    #[test]
    fn time_to_target_interpolates_on_log_log_axes() {
        let pts = [(1.0, 0.4), (4.0, 0.1)];
        assert_eq!(time_to(&pts, 0.5), Some(1.0));
        assert_eq!(time_to(&pts, 0.05), None);
        // 0.2 is halfway between 0.4 and 0.1 on a log axis: halfway in log time = 2 s.
        let t = time_to(&pts, 0.2).unwrap();
        assert!((t - 2.0).abs() < 1e-9, "{t}");
    }

    #[test]
    fn the_recommendation_names_the_first_to_reach_the_tightest_target() {
        let runs = vec![
            run("path/random", &[(1.0, 0.4), (4.0, 0.2)]),
            run("path/sobol", &[(1.0, 0.3), (4.0, 0.1)]),
        ];
        let targets = default_targets(&runs);
        assert_eq!(targets.len(), 3);
        assert!((targets[2] - 0.2).abs() < 1e-12);
        let s = summarise(&runs, targets);
        assert!(
            s.recommendation.contains("path/sobol"),
            "{}",
            s.recommendation
        );
        // Nobody reaches 0.01: the lowest final error is named.
        let s = summarise(&runs, vec![0.01]);
        assert!(
            s.recommendation.contains("path/sobol ("),
            "{}",
            s.recommendation
        );
    }

    #[test]
    fn speedup_is_against_one_worker() {
        let mut a = run("farm:1", &[(10.0, 0.1)]);
        a.workers = Some(1);
        let mut b = run("farm:2", &[(10.0, 0.1)]);
        b.workers = Some(2);
        b.checkpoints[0].samples *= 1.8;
        assert_eq!(speedup(&[b, a]), vec![(1, 1.0), (2, 1.8)]);
    }

    #[test]
    fn csv_has_a_row_per_checkpoint_and_html_escapes() {
        let dir = tempfile::tempdir().unwrap();
        let runs = vec![run("a<b", &[(1.0, 0.4), (2.0, 0.3)])];
        write_csv(&dir.path().join("s.csv"), &runs).unwrap();
        let csv = std::fs::read_to_string(dir.path().join("s.csv")).unwrap();
        assert_eq!(csv.lines().count(), 3);
        let sum = summarise(&runs, vec![0.35]);
        let ctx = Context {
            scene: "s.lxs",
            reference: "r.flm",
            budget: 2.0,
            figure_note: None,
        };
        let h = html(&ctx, &runs, &sum, &[]);
        assert!(h.contains("a&lt;b") && !h.contains("a<b"));
    }
}
