//! `diagnose --format table`: the findings as sentences first, then the
//! residuals per channel (nominal and extended, held-out steps), the noise,
//! and the ranked hypotheses of the first round.

use crate::diagnose::channel::Channel;
use crate::diagnose::noise::Source;
use crate::diagnose::rig::RigPath;
use crate::diagnose::{Diagnosis, structure, words};
use std::fmt::Write;

pub fn table(d: &Diagnosis, rig: &[RigPath], model: &str) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "model {model}: diagnosis against the rig");
    if d.effects.is_empty() {
        let _ = writeln!(
            o,
            "verdict: none. The model explains the data within the noise: no candidate lowers the held-out error significantly."
        );
    }
    for (k, e) in d.effects.iter().enumerate() {
        let _ = writeln!(o, "{}. {}", k + 1, words::sentence(e, &d.noise));
    }
    let total = d.total_gain();
    let patterns = structure::patterns(rig, &d.nominal, &d.noise);
    if !patterns.is_empty() {
        let _ = writeln!(o);
        let _ = writeln!(
            o,
            "what the nominal model gets wrong (channels beyond twice their noise):"
        );
        for p in &patterns {
            let _ = writeln!(o, "  {}", p.sentence);
        }
    }
    let _ = writeln!(o);
    let _ = writeln!(
        o,
        "held-out RMS error (every third step of each path; {} residuals held out, {} fitted):",
        d.held_out, d.training
    );
    let _ = writeln!(
        o,
        "  {:<14} {:>10} {:>10} {:>7} {:>10} {:>10}",
        "channel", "nominal", "extended", "gain", "noise", "noise from"
    );
    let after = d.effects.last().map_or(d.baseline.rms_held_out, |e| {
        e.hypothesis.summary.rms_held_out
    });
    for c in d.channels() {
        let n = d.noise[c.index()];
        let from = match n.source {
            Source::Given => "--noise".to_string(),
            Source::Estimated(k) if c == Channel::Landmarks => format!("{k} dof fit"),
            Source::Estimated(k) => format!("{k} diffs"),
            Source::Floor => "floor".to_string(),
            Source::Absent => continue,
        };
        let _ = writeln!(
            o,
            "  {:<14} {:>10} {:>10} {:>6.0}% {:>10} {:>10}",
            c.name(),
            words::num(d.baseline.rms_held_out[c.index()]),
            words::num(after[c.index()]),
            100.0 * total[c.index()],
            words::num(n.sigma),
            from
        );
    }
    let _ = writeln!(o);
    let _ = writeln!(
        o,
        "hypotheses of the first round (held-out chi-square fall less 2 ln(n) per parameter):"
    );
    for (k, h) in d.hypotheses.iter().enumerate() {
        let _ = writeln!(
            o,
            "  {:>2}. {:<18} {:<12} score {:>12} {}",
            k + 1,
            h.kind.name(),
            h.element_name,
            words::num(h.score),
            if h.significant {
                ""
            } else {
                "(not significant)"
            }
        );
        let _ = writeln!(o, "      {}", words::claim(h));
    }
    for s in &d.skipped {
        let _ = writeln!(
            o,
            "skipped {} {} ({}): {}",
            s.kind.name(),
            s.element_name,
            s.detail,
            s.why
        );
    }
    let _ = writeln!(o, "{} candidates screened, {} fitted", d.screened, d.fitted);
    o
}
