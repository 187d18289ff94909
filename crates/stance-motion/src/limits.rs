//! The `[limits]` section of motion files and joint-path files: which actuator limits the
//! retiming respects, resolved against a robot model.
//!
//! ```text
//! [limits]
//! velocity = 1.0            # fraction of the URDF's <limit velocity>; false for none (default 1.0)
//! acceleration = 30.0       # rad/s^2 (m/s^2 for prismatic joints) for every joint, or
//!                           # { default = 30.0, R_HIP_P = 50.0 }; default: none
//! torque = 1.0              # fraction of the URDF's <limit effort>; false for none (default 1.0)
//! ```
//!
//! A joint whose URDF gives no velocity or effort limit, or a limit `<= 0` (URDF files often
//! write `effort="0"` for "unknown"), has no limit of that kind: the resolved limits
//! ([`ResolvedLimits::joints`]) say so per joint with `null`. Limits are symmetric
//! (`|v| <= V`, `|a| <= A`, `|tau| <= T`) and apply to the movable joints, never to a
//! floating base.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use stance_robot::Model;
use stance_topp::limits::JointLimits;

use crate::StanceError;

/// A fraction of the URDF's limits, or `false` for none.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Scale {
    /// No limit of this kind.
    Off,
    /// The URDF's limits times this factor (> 0).
    Fraction(f64),
}

impl<'de> Deserialize<'de> for Scale {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = Scale;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a fraction of the URDF's limits (a number > 0) or false")
            }
            fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<Scale, E> {
                if v {
                    Err(E::custom(
                        "true is not a fraction: give a number (1.0 for the URDF's limits) or false",
                    ))
                } else {
                    Ok(Scale::Off)
                }
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Scale, E> {
                Ok(Scale::Fraction(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Scale, E> {
                Ok(Scale::Fraction(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Scale, E> {
                Ok(Scale::Fraction(v as f64))
            }
        }
        d.deserialize_any(V)
    }
}

impl Default for Scale {
    fn default() -> Self {
        Scale::Fraction(1.0)
    }
}

/// Acceleration limits: one for every joint, or per joint with an optional default.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum AccelerationSpec {
    /// The same limit for every joint (rad/s^2 or m/s^2).
    All(f64),
    /// Per joint, by URDF name; joints not named take `default` (none without it).
    PerJoint {
        /// Limit of the joints not named.
        #[serde(skip_serializing_if = "Option::is_none")]
        default: Option<f64>,
        /// Joint name -> limit.
        #[serde(flatten)]
        joints: BTreeMap<String, f64>,
    },
}

impl<'de> Deserialize<'de> for AccelerationSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = AccelerationSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "an acceleration limit for every joint (a number), or a map of joint names \
                     to limits with an optional `default`",
                )
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<AccelerationSpec, E> {
                Ok(AccelerationSpec::All(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<AccelerationSpec, E> {
                Ok(AccelerationSpec::All(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<AccelerationSpec, E> {
                Ok(AccelerationSpec::All(v as f64))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<AccelerationSpec, A::Error> {
                let mut joints = BTreeMap::new();
                let mut default = None;
                while let Some((k, v)) = map.next_entry::<String, f64>()? {
                    if k == "default" {
                        default = Some(v);
                    } else if joints.insert(k.clone(), v).is_some() {
                        return Err(serde::de::Error::custom(format!(
                            "{k:?} is given twice: give it once"
                        )));
                    }
                }
                Ok(AccelerationSpec::PerJoint { default, joints })
            }
        }
        d.deserialize_any(V)
    }
}

/// The `[limits]` section (module doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LimitsSpec {
    /// Fraction of the URDF's velocity limits, or `false` (default 1.0).
    #[serde(default)]
    pub velocity: Scale,
    /// Acceleration limits (default: none).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub acceleration: Option<AccelerationSpec>,
    /// Fraction of the URDF's effort limits, or `false` (default 1.0).
    #[serde(default)]
    pub torque: Scale,
}

impl Default for LimitsSpec {
    fn default() -> Self {
        Self {
            velocity: Scale::Fraction(1.0),
            acceleration: None,
            torque: Scale::Fraction(1.0),
        }
    }
}

impl LimitsSpec {
    /// No limits at all (`--no-limits`: contact stability alone).
    ///
    /// ```
    /// let l = stance_motion::limits::LimitsSpec::none();
    /// assert!(l.acceleration.is_none());
    /// ```
    pub fn none() -> Self {
        Self {
            velocity: Scale::Off,
            acceleration: None,
            torque: Scale::Off,
        }
    }
}

/// The limits of one joint as used (`None`: no limit of that kind).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointLimitInfo {
    /// URDF joint name.
    pub name: String,
    /// `|v| <=` this (rad/s or m/s).
    pub velocity: Option<f64>,
    /// `|a| <=` this (rad/s^2 or m/s^2).
    pub acceleration: Option<f64>,
    /// `|tau| <=` this (N m or N).
    pub torque: Option<f64>,
}

/// Limits resolved against a model: per coordinate (the movable joints' velocity entries, in
/// the order given to [`LimitsSpec::resolve`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedLimits {
    /// The limits as the retiming takes them.
    pub limits: JointLimits,
    /// The same per joint, for reports.
    pub joints: Vec<JointLimitInfo>,
}

impl ResolvedLimits {
    /// Whether any limit is finite.
    ///
    /// ```
    /// use stance_motion::limits::LimitsSpec;
    /// let m = stance_robot::Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF,
    ///     &Default::default()).unwrap();
    /// let coords: Vec<usize> = (1..m.joints.len()).filter(|&j| m.joints[j].name != "root_joint").collect();
    /// assert!(!LimitsSpec::none().resolve(&m, &coords).unwrap().any());
    /// ```
    pub fn any(&self) -> bool {
        self.limits.any()
    }
}

/// The movable joint whose name is closest to `name` (edit distance at most a third of its
/// length), for "did you mean" hints.
pub(crate) fn closest_name<'a>(model: &'a Model, name: &str) -> Option<&'a str> {
    model.joints[1..]
        .iter()
        .map(|j| (edit_distance(&j.name, name), j.name.as_str()))
        .filter(|(d, _)| *d <= name.len().max(3) / 3)
        .min()
        .map(|(_, n)| n)
}

/// Levenshtein distance of two strings (by characters).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != *cb))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

fn positive(what: String, v: f64) -> Result<f64, StanceError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(StanceError::BadMotion(format!(
            "{what} is {v}; give a finite number > 0"
        )))
    }
}

impl LimitsSpec {
    /// The limits of the joints `joints` (indices into `model.joints`, each with one velocity
    /// entry) from the URDF's limits and this section.
    ///
    /// # Errors
    ///
    /// [`StanceError::BadMotion`] naming the key: a fraction or an acceleration `<= 0`, NaN or
    /// infinite; an acceleration given for a joint the robot does not have or that is not
    /// among `joints` (locked, or the base).
    ///
    /// ```
    /// use stance_motion::limits::LimitsSpec;
    /// let m = stance_robot::Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF,
    ///     &Default::default()).unwrap();
    /// let coords: Vec<usize> = (2..m.joints.len()).collect();
    /// let spec: LimitsSpec = toml::from_str("acceleration = { default = 20.0, r_knee = 40.0 }").unwrap();
    /// let r = spec.resolve(&m, &coords).unwrap();
    /// let knee = r.joints.iter().find(|j| j.name == "r_knee").unwrap();
    /// assert_eq!(knee.acceleration, Some(40.0));
    /// let bad: LimitsSpec = toml::from_str("acceleration = { r_kneee = 40.0 }").unwrap();
    /// assert!(bad.resolve(&m, &coords).unwrap_err().to_string().contains("r_kneee"));
    /// ```
    pub fn resolve(&self, model: &Model, joints: &[usize]) -> Result<ResolvedLimits, StanceError> {
        let scale = |what: &str, s: Scale| -> Result<Option<f64>, StanceError> {
            match s {
                Scale::Off => Ok(None),
                Scale::Fraction(f) => positive(format!("limits.{what}"), f).map(Some),
            }
        };
        let velocity = scale("velocity", self.velocity)?;
        let torque = scale("torque", self.torque)?;
        let (default_acc, named) = match &self.acceleration {
            None => (None, BTreeMap::new()),
            Some(AccelerationSpec::All(a)) => (
                Some(positive("limits.acceleration".into(), *a)?),
                BTreeMap::new(),
            ),
            Some(AccelerationSpec::PerJoint { default, joints }) => {
                let d = default
                    .map(|a| positive("limits.acceleration.default".into(), a))
                    .transpose()?;
                let mut named = BTreeMap::new();
                for (name, &a) in joints {
                    let a = positive(format!("limits.acceleration.{name}"), a)?;
                    let Some(k) = model.joints.iter().position(|j| &j.name == name) else {
                        let locked = model.locked.iter().any(|(n, _)| n == name);
                        return Err(StanceError::BadMotion(if locked {
                            format!(
                                "limits.acceleration names {name:?}, a locked joint: it does not \
                                 move; remove it"
                            )
                        } else {
                            format!(
                                "limits.acceleration names {name:?}, which is not a joint of the \
                                 robot; use a URDF joint name{}",
                                closest_name(model, name)
                                    .map(|c| format!(" (did you mean {c:?}?)"))
                                    .unwrap_or_default()
                            )
                        }));
                    };
                    named.insert(k, a);
                }
                (d, named)
            }
        };
        let mut limits = JointLimits::none(joints.len());
        let mut info = Vec::with_capacity(joints.len());
        for (c, &k) in joints.iter().enumerate() {
            let j = &model.joints[k];
            let from_urdf = |f: Option<f64>, urdf: f64| {
                f.filter(|_| urdf.is_finite() && urdf > 0.0)
                    .map(|f| f * urdf)
            };
            let v = from_urdf(velocity, j.velocity_limit);
            let t = from_urdf(torque, j.effort_limit);
            let a = named.get(&k).copied().or(default_acc);
            limits.velocity[c] = v.unwrap_or(f64::INFINITY);
            limits.acceleration[c] = a.unwrap_or(f64::INFINITY);
            limits.torque[c] = t.unwrap_or(f64::INFINITY);
            info.push(JointLimitInfo {
                name: j.name.clone(),
                velocity: v,
                acceleration: a,
                torque: t,
            });
        }
        for k in named.keys() {
            if !joints.contains(k) {
                return Err(StanceError::BadMotion(format!(
                    "limits.acceleration names {:?}, which the path does not move (the base or \
                     a joint outside the retimed joints); remove it",
                    model.joints[*k].name
                )));
            }
        }
        Ok(ResolvedLimits {
            limits,
            joints: info,
        })
    }
}
