//! Friction elements (`conventions.md`, "Friction"): the joint they act on,
//! the motion (slide or rotation) that joint must allow, the stick stiffness
//! and the slip limit in the units of that motion.

use super::Checker;
use super::error;
use super::props::Props;
use crate::model::{ElementId, Friction, FrictionId, FrictionMotion, JointId, JointKind, Val};
use crate::syntax::ast::{ElementDecl, ExprKind, Value};
use crate::units::Dim;

/// The motion words of a friction element.
const MOTIONS: [(&str, FrictionMotion); 2] = [
    ("slide", FrictionMotion::Slide),
    ("rotation", FrictionMotion::Rotation),
];

/// The motion a friction follows when it names none: the slide of a joint
/// that slides, else the rotation.
pub fn default_motion(kind: JointKind) -> FrictionMotion {
    match kind {
        JointKind::Cylindrical | JointKind::Translational => FrictionMotion::Slide,
        _ => FrictionMotion::Rotation,
    }
}

/// Whether a joint has the axis a friction of this motion acts along.
pub fn allows(kind: JointKind, motion: FrictionMotion) -> bool {
    match motion {
        FrictionMotion::Slide => matches!(kind, JointKind::Cylindrical | JointKind::Translational),
        FrictionMotion::Rotation => matches!(
            kind,
            JointKind::Revolute | JointKind::Cylindrical | JointKind::Spherical
        ),
    }
}

pub fn motion_word(m: FrictionMotion) -> &'static str {
    match m {
        FrictionMotion::Slide => "slide",
        FrictionMotion::Rotation => "rotation",
    }
}

impl Checker {
    /// Frictions are checked after every joint, so they may come before theirs.
    pub(super) fn friction(&mut self, e: &ElementDecl) {
        let keys = crate::model::schema::FRICTION.keys();
        let props = self.props("friction", e, &keys);
        let joint = self.friction_joint(&props);
        let motion = match props.get("motion") {
            None => joint.map(|j| default_motion(self.model.joints[j.index()].kind)),
            Some(p) => match self.word(&p.value) {
                Some(w) => match MOTIONS.iter().find(|(n, _)| *n == w) {
                    Some(&(_, m)) => Some(m),
                    None => {
                        self.problems.push(error::unknown_name(
                            "friction motion",
                            w,
                            p.value.span(),
                            MOTIONS.iter().map(|(n, _)| *n),
                        )
                        .note("a friction's motion is `slide` (along z of the joint's J marker) or `rotation` (about it)"));
                        None
                    }
                },
                None => {
                    self.problems.push(error::wrong_value_kind(
                        "`slide` or `rotation`",
                        "a value",
                        p.value.span(),
                        "motion slide",
                    ));
                    None
                }
            },
        };
        let (kf_dim, limit_dim, kf_ex, limit_ex) = match motion {
            Some(FrictionMotion::Rotation) => (
                Dim::ROT_STIFFNESS,
                Dim::TORQUE,
                "kf 50000 N*mm/deg",
                "limit 2000 N*mm",
            ),
            _ => (Dim::STIFFNESS, Dim::FORCE, "kf 1000 N/mm", "limit 150 N"),
        };
        let name = &e.name.name;
        let kf = self.friction_value(
            &props,
            "kf",
            kf_dim,
            kf_ex,
            |v| v > 0.0,
            || error::friction_stiffness_not_positive,
        );
        let limit = self.friction_value(
            &props,
            "limit",
            limit_dim,
            limit_ex,
            |v| v >= 0.0,
            || error::friction_limit_negative,
        );
        let (Some(joint), Some(motion), Some(stiffness), Some(limit)) = (joint, motion, kf, limit)
        else {
            return;
        };
        let j = &self.model.joints[joint.index()];
        if !allows(j.kind, motion) {
            let at = props.get("joint").map_or(e.name.span, |p| p.value.span());
            let decl = self.model.origins.get(ElementId::Joint(joint));
            let d = error::friction_without_axis(
                name,
                &j.name,
                j.kind.keyword(),
                motion_word(motion),
                at,
                decl,
            );
            self.problems.push(d);
            return;
        }
        let id = FrictionId(self.model.frictions.len() as u32);
        self.model
            .origins
            .insert(ElementId::Friction(id), e.name.span);
        self.model.frictions.push(Friction {
            name: name.clone(),
            joint,
            motion,
            stiffness,
            limit,
        });
    }

    /// A bare word (`L5`, `slide`) written as a value.
    fn word<'v>(&self, v: &'v Value) -> Option<&'v str> {
        match v {
            Value::Expr(e) => match &e.kind {
                ExprKind::Param(id) => Some(id.name.as_str()),
                _ => None,
            },
            _ => None,
        }
    }

    fn friction_joint(&mut self, props: &Props) -> Option<JointId> {
        let Some(p) = props.get("joint") else {
            if !props.had_unknown {
                self.problems.push(error::missing_property(
                    "friction",
                    &props.decl.name.name,
                    "joint",
                    props.decl.name.span,
                    "joint L5",
                ));
            }
            return None;
        };
        let Some(w) = self.word(&p.value) else {
            self.problems.push(error::wrong_value_kind(
                "a joint name",
                "a value",
                p.value.span(),
                "joint L5",
            ));
            return None;
        };
        match self.model.joints.iter().position(|j| j.name == w) {
            Some(k) => {
                // For editors: `joint L5` names the joint (definition, rename).
                self.resolution
                    .refer(p.value.span(), ElementId::Joint(JointId(k as u32)));
                Some(JointId(k as u32))
            }
            None => {
                let names: Vec<&str> = self.model.joints.iter().map(|j| j.name.as_str()).collect();
                self.problems
                    .push(error::unknown_name("joint", w, p.value.span(), names));
                None
            }
        }
    }

    /// `kf` or `limit`: required, in `dim`, and `ok` (else the diagnostic of `bad`).
    fn friction_value(
        &mut self,
        props: &Props,
        key: &str,
        dim: Dim,
        example: &str,
        ok: impl Fn(f64) -> bool,
        bad: impl Fn() -> fn(&str, crate::span::Span) -> crate::diagnostic::Diagnostic,
    ) -> Option<Val> {
        let Some(p) = props.get(key) else {
            if !props.had_unknown {
                self.problems.push(error::missing_property(
                    "friction",
                    &props.decl.name.name,
                    key,
                    props.decl.name.span,
                    example,
                ));
            }
            return None;
        };
        let v = self.prop_scalar(p, dim, example.split_once(' ').map_or(example, |s| s.1))?;
        if !ok(v.value) {
            self.problems
                .push(bad()(&props.decl.name.name, p.value.span()));
            return None;
        }
        Some(v)
    }
}
