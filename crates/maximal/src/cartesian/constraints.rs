//! The building blocks of the holonomic constraints `Φ(z, t) = 0` (rails, ropes, pins, rods),
//! from which each scene's file in `src/scenes/` writes its constraints by hand as the joints,
//! ropes, rails and inclines act on the bodies — independently of the reduced model's poses.
//!
//! `z` holds every body's pose `(x_b, y_b, φ_b)`, body-major, in the reduced model's body order.
//! Every constraint is evaluated generically over the scalar, so that `Φ_z`, `Φ_t` and the
//! convective term `γ_Φ` come from dual-number passes over the same code.

use lagrange::graph::GraphMechanism;
use lagrange::{Pose, Scalar};
use std::sync::Arc;

/// Index of `x` within a body's pose.
pub(crate) const X: usize = 0;
/// Index of `y` within a body's pose.
pub(crate) const Y: usize = 1;
/// Index of `φ` within a body's pose.
pub(crate) const ANGLE: usize = 2;

/// A point of the plane that a joint attaches to.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Anchor {
    /// A fixed point of the world frame.
    World {
        /// `x` (m).
        x: f64,
        /// `y` (m).
        y: f64,
    },
    /// The horizontally driven support `(A sin ωt, 0)` of the driven pendulum.
    Driven {
        /// Amplitude `A` (m).
        amplitude: f64,
        /// Angular frequency `ω` (rad/s).
        frequency: f64,
    },
    /// A driven support seen from a frame whose origin is elsewhere: `centre + (A sin ωt, 0)`
    /// ([`Anchor::moved`]).
    DrivenFrom {
        /// Amplitude `A` (m).
        amplitude: f64,
        /// Angular frequency `ω` (rad/s).
        frequency: f64,
        /// Where the support's centre is (m).
        centre: [f64; 2],
    },
    /// The point at `offset` in the frame of body `body`: `p_b + R(φ_b) offset`.
    Body {
        /// Index of the body.
        body: usize,
        /// Position in the body frame (m).
        offset: [f64; 2],
    },
}

impl Anchor {
    /// The world position of the anchor at `(z, t)`.
    fn position<S: Scalar>(&self, z: &[S], t: S) -> [S; 2] {
        match *self {
            Anchor::World { x, y } => [S::from(x), S::from(y)],
            Anchor::Driven { amplitude, frequency } => [(t * frequency).sin() * amplitude, S::zero()],
            Anchor::DrivenFrom { amplitude, frequency, centre: [x, y] } => {
                [(t * frequency).sin() * amplitude + x, S::from(y)]
            }
            Anchor::Body { body, offset: [u, v] } => {
                let (x, y) = (z[3 * body + X], z[3 * body + Y]);
                let (sin, cos) = z[3 * body + ANGLE].sin_cos();
                [x + cos * u - sin * v, y + sin * u + cos * v]
            }
        }
    }

    /// Whether the anchor moves with time by itself.
    fn is_driven(&self) -> bool {
        matches!(self, Anchor::Driven { .. } | Anchor::DrivenFrom { .. })
    }

    /// The same anchor in a frame whose origin is at `origin` (world coordinates): fixed and
    /// driven points move by `−origin`, points of bodies stay in their bodies.
    fn moved(&self, origin: [f64; 2]) -> Anchor {
        match *self {
            Anchor::World { x, y } => Anchor::World { x: x - origin[0], y: y - origin[1] },
            Anchor::Driven { amplitude, frequency } => {
                Anchor::DrivenFrom { amplitude, frequency, centre: [-origin[0], -origin[1]] }
            }
            Anchor::DrivenFrom { amplitude, frequency, centre } => {
                Anchor::DrivenFrom { amplitude, frequency, centre: [centre[0] - origin[0], centre[1] - origin[1]] }
            }
            Anchor::Body { .. } => self.clone(),
        }
    }

    /// The origin of the world frame.
    pub(crate) const ORIGIN: Anchor = Anchor::World { x: 0.0, y: 0.0 };

    /// The point at `(u, v)` in the frame of `body`.
    pub(crate) fn on(body: usize, u: f64, v: f64) -> Anchor {
        Anchor::Body { body, offset: [u, v] }
    }
}

/// What a constraint ties together.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Joint {
    /// `Σ_k c_k z_k + c₀ = 0` (one equation): rails, fixed coordinates, ropes over pulleys,
    /// a rope that does not slip on its pulley, a block on an incline.
    Linear {
        /// `(index into z, coefficient c_k)`.
        terms: Vec<(usize, f64)>,
        /// `c₀`.
        constant: f64,
    },
    /// The distance between two anchors is `length` (one equation): a massless rod between
    /// point masses, or a point mass and a support.
    Distance {
        /// One end.
        from: Anchor,
        /// The other end.
        to: Anchor,
        /// The rod's length (m).
        length: f64,
    },
    /// Joint `joint` of a joint graph between its two bodies' poses
    /// ([`GraphMechanism::joint_residuals`]): the joint's own rows, then its drive or coupling.
    Graph {
        /// The graph's model.
        mechanism: Arc<GraphMechanism>,
        /// The joint's index.
        joint: usize,
    },
}

/// One named holonomic constraint, one or two equations of `Φ(z, t) = 0`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Constraint {
    /// What it is, in words, for error messages (`rod pin of bob on cart (x)` …).
    pub(crate) name: String,
    /// What it ties together.
    pub(crate) joint: Joint,
}

impl Constraint {
    /// Number of scalar equations.
    pub(crate) fn equations(&self) -> usize {
        match &self.joint {
            Joint::Linear { .. } | Joint::Distance { .. } => 1,
            Joint::Graph { mechanism, joint } => mechanism.joint_rows(*joint),
        }
    }

    /// Whether `Φ` depends on `t` explicitly (a rheonomic constraint).
    pub(crate) fn is_rheonomic(&self) -> bool {
        match &self.joint {
            Joint::Linear { .. } => false,
            Joint::Distance { from: a, to: b, .. } => a.is_driven() || b.is_driven(),
            Joint::Graph { mechanism, joint } => mechanism.drive(*joint).is_some_and(|p| p.varies()),
        }
    }

    /// The same constraint in a frame whose origin is at `origin` (world coordinates), with the
    /// joint graph `moved` (the same graph in that frame) for a graph joint: bodies at `z − origin`
    /// satisfy it exactly where bodies at `z` satisfied the original.
    pub(crate) fn moved(&self, origin: [f64; 2], moved: Option<&Arc<GraphMechanism>>) -> Constraint {
        let joint = match &self.joint {
            Joint::Linear { terms, constant } => {
                // Σ c_k (z_k + o_k) + c₀ = Σ c_k z_k + (c₀ + Σ c_k o_k), o_k the origin's x or y.
                let shift: f64 = terms.iter().filter(|(k, _)| k % 3 != ANGLE).map(|&(k, c)| c * origin[k % 3]).sum();
                Joint::Linear { terms: terms.clone(), constant: constant + shift }
            }
            Joint::Distance { from, to, length } => {
                Joint::Distance { from: from.moved(origin), to: to.moved(origin), length: *length }
            }
            Joint::Graph { mechanism, joint } => {
                Joint::Graph { mechanism: Arc::clone(moved.unwrap_or(mechanism)), joint: *joint }
            }
        };
        Constraint { name: self.name.clone(), joint }
    }

    /// Write the constraint's [`equations`](Self::equations) values at `(z, t)` into `out`.
    pub(crate) fn evaluate<S: Scalar>(&self, z: &[S], t: S, out: &mut [S]) {
        match &self.joint {
            Joint::Linear { terms, constant } => {
                let mut value = S::from(*constant);
                for &(k, c) in terms {
                    value += z[k] * c;
                }
                out[0] = value;
            }
            Joint::Distance { from, to, length } => {
                let ([xa, ya], [xb, yb]) = (from.position(z, t), to.position(z, t));
                let (dx, dy) = (xa - xb, ya - yb);
                out[0] = (dx * dx + dy * dy).sqrt() - *length;
            }
            Joint::Graph { mechanism, joint } => {
                let pose = |b: usize| Pose::new(z[3 * b + X], z[3 * b + Y], z[3 * b + ANGLE]);
                mechanism.joint_residuals(*joint, t, &pose, out);
            }
        }
    }
}

/// Evaluate every constraint at `(z, t)`: `Φ` (m) into `phi`.
pub(crate) fn evaluate_all<S: Scalar>(constraints: &[Constraint], z: &[S], t: S, phi: &mut [S]) {
    let mut row = 0;
    for constraint in constraints {
        let rows = constraint.equations();
        constraint.evaluate(z, t, &mut phi[row..row + rows]);
        row += rows;
    }
    debug_assert_eq!(row, phi.len(), "one value per equation");
}

/// The name of every scalar equation, in the order of `Φ` (a pin's two equations are suffixed
/// `(x)` and `(y)`).
pub(crate) fn equation_names(constraints: &[Constraint]) -> Vec<String> {
    let mut names = Vec::new();
    for constraint in constraints {
        if let Joint::Graph { mechanism, joint } = &constraint.joint {
            names.extend(mechanism.joint_row_names(*joint));
        } else if constraint.equations() == 2 {
            names.push(format!("{} (x)", constraint.name));
            names.push(format!("{} (y)", constraint.name));
        } else {
            names.push(constraint.name.clone());
        }
    }
    names
}

/// `z[3 body + component] = value`.
pub(crate) fn fix(body: usize, component: usize, value: f64, name: String) -> Constraint {
    Constraint { name, joint: Joint::Linear { terms: vec![(3 * body + component, 1.0)], constant: -value } }
}

/// `Σ c_k z_k + c₀ = 0` over `(body, component, c_k)`.
pub(crate) fn linear(terms: &[(usize, usize, f64)], constant: f64, name: &str) -> Constraint {
    let terms = terms.iter().map(|&(body, component, c)| (3 * body + component, c)).collect();
    Constraint { name: name.into(), joint: Joint::Linear { terms, constant } }
}

/// A point mass's orientation, which nothing else fixes: `φ_b = 0`.
pub(crate) fn no_turning(body: usize, names: &[String]) -> Constraint {
    fix(body, ANGLE, 0.0, format!("{} does not turn", names[body]))
}

/// The frame a vector of a [`VelocityConstraint`] is fixed in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Frame {
    /// Turns with the body: `R(φ_b) v`.
    Body,
    /// Fixed in the world.
    World,
}

/// One velocity (non-holonomic) constraint `A(z) ż = 0`: the velocity of a point of body `body`
/// has no component along `direction`, `(v_b + φ̇_b ẑ × r) · w = 0`, with the lever arm `r` from
/// the body's centre to the point and the direction `w` each fixed in the body or in the world
/// (a knife edge: both in the body; rolling contact: both in the world, the contact point being
/// the material point at a fixed offset from the centre).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct VelocityConstraint {
    /// What it is, in words, for error messages.
    pub(crate) name: String,
    /// Index of the body.
    pub(crate) body: usize,
    /// Lever arm `r` from the body's centre to the point (m), and its frame.
    pub(crate) arm: ([f64; 2], Frame),
    /// The direction `w` along which the point may not move, and its frame.
    pub(crate) direction: ([f64; 2], Frame),
}

impl VelocityConstraint {
    /// The residual `(v_b + φ̇_b ẑ × r) · w` at `(z, ż)`; linear in `ż`.
    pub(crate) fn evaluate<S: Scalar>(&self, z: &[S], zdot: &[S]) -> S {
        let b = 3 * self.body;
        let (sin, cos) = z[b + ANGLE].sin_cos();
        let turned = |(v, frame): ([f64; 2], Frame)| match frame {
            Frame::Body => [cos * v[0] - sin * v[1], sin * v[0] + cos * v[1]],
            Frame::World => [S::from(v[0]), S::from(v[1])],
        };
        let ([rx, ry], [wx, wy]) = (turned(self.arm), turned(self.direction));
        let omega = zdot[b + ANGLE];
        // ẑ × r = (−r_y, r_x).
        let (vx, vy) = (zdot[b + X] - omega * ry, zdot[b + Y] + omega * rx);
        vx * wx + vy * wy
    }
}
