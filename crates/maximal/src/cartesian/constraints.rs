//! The holonomic constraints `Φ(z, t) = 0` of every scene, written by hand as the joints,
//! ropes, rails and inclines act on the bodies — independently of the reduced model's poses.
//!
//! `z` holds every body's pose `(x_b, y_b, φ_b)`, body-major, in the reduced model's body order.
//! Every constraint is evaluated generically over the scalar, so that `Φ_z`, `Φ_t` and the
//! convective term `γ_Φ` come from dual-number passes over the same code.

use lagrange::Scalar;
use lagrange_scenes::Params;
use std::f64::consts::PI;

/// Index of `x` within a body's pose.
const X: usize = 0;
/// Index of `y` within a body's pose.
const Y: usize = 1;
/// Index of `φ` within a body's pose.
const ANGLE: usize = 2;

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
            Anchor::Body { body, offset: [u, v] } => {
                let (x, y) = (z[3 * body + X], z[3 * body + Y]);
                let (sin, cos) = z[3 * body + ANGLE].sin_cos();
                [x + cos * u - sin * v, y + sin * u + cos * v]
            }
        }
    }

    /// Whether the anchor moves with time by itself.
    fn is_driven(&self) -> bool {
        matches!(self, Anchor::Driven { .. })
    }

    /// The origin of the world frame.
    const ORIGIN: Anchor = Anchor::World { x: 0.0, y: 0.0 };

    /// The point at `(u, v)` in the frame of `body`.
    fn on(body: usize, u: f64, v: f64) -> Anchor {
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
    /// Two anchors coincide (two equations, `x` then `y`): a revolute pin.
    Pin(Anchor, Anchor),
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
        match self.joint {
            Joint::Pin(..) => 2,
            Joint::Linear { .. } | Joint::Distance { .. } => 1,
        }
    }

    /// Whether `Φ` depends on `t` explicitly (a rheonomic constraint).
    pub(crate) fn is_rheonomic(&self) -> bool {
        match &self.joint {
            Joint::Linear { .. } => false,
            Joint::Pin(a, b) | Joint::Distance { from: a, to: b, .. } => a.is_driven() || b.is_driven(),
        }
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
            Joint::Pin(a, b) => {
                let ([xa, ya], [xb, yb]) = (a.position(z, t), b.position(z, t));
                out[0] = xa - xb;
                out[1] = ya - yb;
            }
            Joint::Distance { from, to, length } => {
                let ([xa, ya], [xb, yb]) = (from.position(z, t), to.position(z, t));
                let (dx, dy) = (xa - xb, ya - yb);
                out[0] = (dx * dx + dy * dy).sqrt() - *length;
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
        if constraint.equations() == 2 {
            names.push(format!("{} (x)", constraint.name));
            names.push(format!("{} (y)", constraint.name));
        } else {
            names.push(constraint.name.clone());
        }
    }
    names
}

/// `z[3 body + component] = value`.
fn fix(body: usize, component: usize, value: f64, name: String) -> Constraint {
    Constraint { name, joint: Joint::Linear { terms: vec![(3 * body + component, 1.0)], constant: -value } }
}

/// `Σ c_k z_k + c₀ = 0` over `(body, component, c_k)`.
fn linear(terms: &[(usize, usize, f64)], constant: f64, name: &str) -> Constraint {
    let terms = terms.iter().map(|&(body, component, c)| (3 * body + component, c)).collect();
    Constraint { name: name.into(), joint: Joint::Linear { terms, constant } }
}

/// A point mass's orientation, which nothing else fixes: `φ_b = 0`.
fn no_turning(body: usize, names: &[String]) -> Constraint {
    fix(body, ANGLE, 0.0, format!("{} does not turn", names[body]))
}

/// A point mass hung at a fixed horizontal position `x_b = x`, not turning (2 constraints).
fn hanging(body: usize, x: f64, names: &[String]) -> [Constraint; 2] {
    [fix(body, X, x, format!("{} hangs at x = {x}", names[body])), no_turning(body, names)]
}

/// A revolute pin between two anchors.
fn pin(a: Anchor, b: Anchor, name: String) -> Constraint {
    Constraint { name, joint: Joint::Pin(a, b) }
}

/// The constraints of `scene` with `params` (validated by the caller: every parameter the
/// scene reads exists), for bodies named `names` in the reduced model's order; `None` for a
/// scene no constraints are written for.
///
/// Each scene's constraints fix exactly `3B − n` coordinates, `n` the reduced model's degrees
/// of freedom; depths are `−y` (the pulley scenes measure them downward, SYSTEMS.md §4–§6).
pub(crate) fn scene_constraints(scene: &str, params: &Params, names: &[String]) -> Option<Vec<Constraint>> {
    let p = |name: &str| params.get(name);
    let constraints = match scene {
        // Cart (0) on the rail y = 0, not turning; the bob (1) hangs from the cart by a rod
        // of length r: the rod end (0, r) in the bob's frame is pinned to the cart's centre.
        // For a point bob the pin fixes φ_bob too (the rod's direction); for a compound bob
        // φ_bob is the rod's angle θ either way.
        "cart_pendulum" => {
            let r = p("rod_length");
            vec![
                fix(0, Y, 0.0, "cart on the rail (y = 0)".into()),
                no_turning(0, names),
                pin(Anchor::on(1, 0.0, r), Anchor::on(0, 0.0, 0.0), "rod pin of the bob on the cart".into()),
            ]
        }
        // The mass slides on the x axis: y = 0 and no turning (SYSTEMS.md §2).
        "harmonic_oscillator" => vec![fix(0, Y, 0.0, "mass on the x axis (y = 0)".into()), no_turning(0, names)],
        // Free particles in the plane: only the point mass's orientation is fixed.
        "kepler" | "isotropic_oscillator" | "spring_pendulum" | "charged_particle" => vec![no_turning(0, names)],
        // m1 (0) hangs at x = −a, m2 (1) at x = +a, the pulley (2) turns about the origin.
        // Rope: depths x1 + x2 = l − πa, i.e. −y1 − y2 − (l − πa) = 0. No slip: the pulley
        // turns by x1/a (SYSTEMS.md §4: φ = x/a with x = −y1), i.e. a φ_pulley + y1 = 0.
        "atwood" => {
            let (a, l) = (p("pulley_radius"), p("rope_length"));
            let mut c: Vec<Constraint> = hanging(0, -a, names).into_iter().chain(hanging(1, a, names)).collect();
            c.push(fix(2, X, 0.0, "pulley axle at x = 0".into()));
            c.push(fix(2, Y, 0.0, "pulley axle at y = 0".into()));
            c.push(linear(&[(0, Y, -1.0), (1, Y, -1.0)], -(l - PI * a), "rope over the pulley"));
            c.push(linear(&[(2, ANGLE, a), (0, Y, 1.0)], 0.0, "rope does not slip on the pulley"));
            c
        }
        // m1 (0), m2 (1), m3 (2), movable pulley P (3), all on the vertical x = 0, not turning.
        // Upper rope: x1 + x_P = l; lower rope: (x2 − x_P) + (x3 − x_P) = l' (depths; SYSTEMS.md §5).
        "double_atwood" => {
            let (l, l_lower) = (p("rope_length"), p("lower_rope_length"));
            let mut c: Vec<Constraint> = (0..4).flat_map(|b| hanging(b, 0.0, names)).collect();
            c.push(linear(&[(0, Y, -1.0), (3, Y, -1.0)], -l, "upper rope"));
            c.push(linear(&[(1, Y, -1.0), (2, Y, -1.0), (3, Y, 2.0)], -l_lower, "lower rope"));
            c
        }
        // Pulleys A (0) and B (1), m2 (2), m3 (3) on B, m4 (4), m5 (5) on A, all on x = 0, not
        // turning. Upper rope: x_A + x_B = l; B's rope: (x2 − x_B) + (x3 − x_B) = l';
        // A's rope: (x4 − x_A) + (x5 − x_A) = l'' (depths; SYSTEMS.md §6).
        "double_double_atwood" => {
            let (l, l_b, l_a) = (p("rope_length"), p("rope_length_b"), p("rope_length_a"));
            let mut c: Vec<Constraint> = (0..6).flat_map(|b| hanging(b, 0.0, names)).collect();
            c.push(linear(&[(0, Y, -1.0), (1, Y, -1.0)], -l, "upper rope"));
            c.push(linear(&[(2, Y, -1.0), (3, Y, -1.0), (1, Y, 2.0)], -l_b, "rope of pulley B"));
            c.push(linear(&[(4, Y, -1.0), (5, Y, -1.0), (0, Y, 2.0)], -l_a, "rope of pulley A"));
            c
        }
        // Wedge (0) on the floor, not turning; the block (1) on the incline through the top
        // corner (x_w, L sin α) with direction (cos α, −sin α), i.e. normal (sin α, cos α):
        // (sin α, cos α)·(p_block − (x_w, L sin α)) = 0 (SYSTEMS.md §7).
        "wedge" => {
            let (alpha, length) = (p("angle"), p("incline_length"));
            let (sin, cos) = alpha.sin_cos();
            vec![
                fix(0, Y, 0.0, "wedge on the floor (y = 0)".into()),
                no_turning(0, names),
                linear(&[(1, X, sin), (0, X, -sin), (1, Y, cos)], -length * sin * cos, "block on the incline"),
                no_turning(1, names),
            ]
        }
        // Rod 1 from the origin to bob 1: the rod end (0, l1) in bob 1's frame is pinned to the
        // origin; rod 2's end (0, l2) in bob 2's frame is pinned to bob 1's centre. Valid for
        // point and compound bobs (the bobs turn with their rods).
        "double_pendulum" => {
            let (l1, l2) = (p("length_1"), p("length_2"));
            vec![
                pin(Anchor::on(0, 0.0, l1), Anchor::ORIGIN, "rod 1 pinned at the origin".into()),
                pin(Anchor::on(1, 0.0, l2), Anchor::on(0, 0.0, 0.0), "rod 2 pinned at bob 1".into()),
            ]
        }
        // Uniform links of length l: link 1's top end (0, l/2) pinned to the origin, each
        // link's top end pinned to the previous link's bottom end (0, −l/2).
        "chain" => {
            let half = 0.5 * p("link_length");
            let mut c =
                vec![pin(Anchor::on(0, 0.0, half), Anchor::ORIGIN, format!("{} pinned at the origin", names[0]))];
            for i in 1..names.len() {
                let name = format!("{} pinned to {}", names[i], names[i - 1]);
                c.push(pin(Anchor::on(i, 0.0, half), Anchor::on(i - 1, 0.0, -half), name));
            }
            c
        }
        // The point bob at distance l from the moving support (A sin ωt, 0): a rheonomic rod
        // (the bob's pose angle is 0 in the reduced model, so the rod is a distance constraint).
        "driven_pendulum" => {
            let support = Anchor::Driven { amplitude: p("amplitude"), frequency: p("drive_frequency") };
            let rod = Joint::Distance { from: Anchor::on(0, 0.0, 0.0), to: support, length: p("length") };
            vec![Constraint { name: "rod to the driven support".into(), joint: rod }, no_turning(0, names)]
        }
        _ => return None,
    };
    Some(constraints)
}
