//! `diagnose --format json` (`interfaces.md`): `baseline`, `hypotheses`,
//! `verdict`, `effects`, extended with the noise used, where it came from,
//! each parameter's interval and the held-out split. Numbers in boundary
//! units; an undetermined parameter is `null`, never a number.

use crate::diagnose::channel::PerChannel;
use crate::diagnose::noise::Source;
use crate::diagnose::rig::RigPath;
use crate::diagnose::{Diagnosis, Effect, Hypothesis, ParamResult, structure, words};
use serde_json::{Map, Value, json};

fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

/// The measured channels' figures (`landmarks_mm` only with landmark data).
fn channels(d: &Diagnosis, v: &PerChannel) -> Value {
    let mut m = Map::new();
    for c in d.channels() {
        m.insert(c.name().into(), num(v[c.index()]));
    }
    Value::Object(m)
}

fn params(ps: &[ParamResult]) -> (Value, Value) {
    let (mut values, mut intervals) = (Map::new(), Map::new());
    for p in ps {
        values.insert(p.name.clone(), p.value.map_or(Value::Null, num));
        intervals.insert(
            p.name.clone(),
            p.interval
                .map_or(Value::Null, |(a, b)| json!([num(a), num(b)])),
        );
    }
    (Value::Object(values), Value::Object(intervals))
}

fn hypothesis(d: &Diagnosis, rank: usize, h: &Hypothesis) -> Value {
    let (values, intervals) = params(&h.params);
    json!({
        "rank": rank,
        "kind": h.kind.name(),
        "element": h.element_name,
        "detail": words::claim(h),
        "params": values,
        "intervals": intervals,
        "units": h.params.iter().map(|p| (p.name.clone(), json!(p.unit))).collect::<Map<_, _>>(),
        "rms_after": channels(d, &h.summary.rms_held_out),
        "score": num(h.score),
        "significant": h.significant,
    })
}

fn effect(e: &Effect, d: &Diagnosis) -> Value {
    let (values, intervals) = params(&e.hypothesis.params);
    json!({
        "kind": e.hypothesis.kind.name(),
        "element": e.hypothesis.element_name,
        "params": values,
        "intervals": intervals,
        "gain": channels(d, &e.gain),
        "finding": words::sentence(e, &d.noise),
    })
}

pub fn to_json(d: &Diagnosis, rig: &[RigPath]) -> Value {
    let noise: Map<String, Value> = d
        .channels()
        .into_iter()
        .map(|c| {
            let n = d.noise[c.index()];
            let source = match n.source {
                Source::Given => "given",
                Source::Estimated(_) => "estimated",
                Source::Floor => "floor",
                Source::Absent => "absent",
            };
            (
                c.name().to_string(),
                json!({ "sigma": num(n.sigma), "source": source }),
            )
        })
        .collect();
    let verdict = match d.effects.first() {
        Some(e) => json!({
            "kind": e.hypothesis.kind.name(),
            "element": e.hypothesis.element_name,
            "gain": channels(d, &d.total_gain()),
        }),
        None => json!({ "kind": "none", "element": null, "gain": channels(d, &[0.0; 6]) }),
    };
    json!({
        "baseline": {
            "rms": channels(d, &d.baseline.rms),
            "rms_held_out": channels(d, &d.baseline.rms_held_out),
        },
        "noise": noise,
        "residual_structure": structure::patterns(rig, &d.nominal, &d.noise).iter().map(|p| json!({
            "path": p.path, "channel": p.channel.name(), "rms": num(p.rms), "shape": p.shape,
            "hysteresis": p.hysteresis.map_or(Value::Null, num),
            "worst_at": { "load": p.worst_at.0, "value": num(p.worst_at.1) },
            "sentence": p.sentence,
        })).collect::<Vec<_>>(),
        "held_out": { "rule": "every third step of each path", "residuals": d.held_out, "training_residuals": d.training },
        "hypotheses": d.hypotheses.iter().enumerate().map(|(k, h)| hypothesis(d, k + 1, h)).collect::<Vec<_>>(),
        "verdict": verdict,
        "effects": d.effects.iter().map(|e| effect(e, d)).collect::<Vec<_>>(),
        "skipped": d.skipped.iter().map(|s| json!({
            "kind": s.kind.name(), "element": s.element_name, "detail": s.detail, "why": s.why,
        })).collect::<Vec<_>>(),
    })
}
