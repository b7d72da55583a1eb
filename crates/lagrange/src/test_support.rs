//! Small mechanisms for the solver's own unit tests (the scenes crate has the real ones).
//!
//! The unit tests cannot use `lagrange-scenes` instead: it depends on `lagrange`, so as a
//! dev-dependency it would bring a second copy of this crate whose `Mechanism` is a different
//! trait from the one under test. These stay minimal (no parameters, no closed forms beyond
//! the one each test needs).

use crate::{Body, Coordinate, Description, Lagrangian, Mechanism, Pose, Scalar};

/// Pendulum on a cart (docs/scenes.md#cart_pendulum): q = (X, θ).
#[derive(Clone, Debug)]
pub(crate) struct Cart {
    pub description: Description,
    pub cart: f64,
    pub bob: f64,
    pub r: f64,
    pub g: f64,
}

/// The cart pendulum: cart of mass `cart`, bob of mass `bob` on a rod `r`, `g = 9.81`.
pub(crate) fn cart(cart: f64, bob: f64, r: f64) -> Cart {
    let g = 9.81;
    let description = Description::new().length("X").angle("θ").point("cart", cart).point("bob", bob).gravity(g);
    Cart { description, cart, bob, r, g }
}

impl Cart {
    /// The closed form of docs/scenes.md#cart_pendulum.
    pub(crate) fn closed_form(&self, q: &[f64], v: &[f64]) -> [f64; 2] {
        let (big, m, r, g) = (self.cart, self.bob, self.r, self.g);
        let (s, c) = q[1].sin_cos();
        let den = big + m * s * s;
        [m * s * (r * v[1] * v[1] + g * c) / den, -((big + m) * g * s + m * r * v[1] * v[1] * s * c) / (r * den)]
    }
}

impl Mechanism for Cart {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0], S::zero());
        p[1] = Pose::point(q[0] + q[1].sin() * self.r, -q[1].cos() * self.r);
    }
}

/// A mass `m` on a spring `k` whose anchor moves as `A sin t`, with viscous damping `c`:
/// `V = ½ k (x − A sin t)²` (through the pose), `m ẍ = −k (x − A sin t) − c ẋ`; a constant mass
/// matrix. With `A = 0` ([`Spring::new`]) the damped harmonic oscillator.
#[derive(Clone, Debug)]
pub(crate) struct Spring {
    pub description: Description,
    pub k: f64,
    pub c: f64,
    pub amplitude: f64,
}

impl Spring {
    /// `m ẍ = −k x − c ẋ`.
    pub(crate) fn new(m: f64, k: f64, c: f64) -> Self {
        let description = Description::new().length("x").point("mass", m).with_constant_mass_matrix();
        Self { description, k, c, amplitude: 0.0 }
    }

    /// A stiff spring whose anchor moves slowly, undamped: from `x = 0`,
    /// `ẋ = A ω²/(ω² − 1)` (`ω² = k/m`) the motion is exactly the slow `x = A ω²/(ω² − 1) sin t`,
    /// with the fast mode (frequency `ω`) not excited.
    pub(crate) fn driven(m: f64, k: f64, amplitude: f64) -> Self {
        Self { amplitude, ..Self::new(m, k, 0.0) }
    }

    /// `ω²/(ω² − 1) A`: the amplitude of the slow solution.
    pub(crate) fn slow_amplitude(&self) -> f64 {
        let omega2 = self.k / self.description.bodies[0].mass;
        self.amplitude * omega2 / (omega2 - 1.0)
    }
}

impl Mechanism for Spring {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0], S::zero());
    }
    fn potential<S: Scalar>(&self, t: S, _q: &[S], p: &[Pose<S>]) -> Option<S> {
        let stretch = p[0].x - t.sin() * self.amplitude;
        Some(stretch * stretch * (0.5 * self.k))
    }
    fn generalized_force<S: Scalar>(&self, _t: S, _q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        if self.c == 0.0 {
            return false;
        }
        force[0] -= qdot[0] * self.c;
        true
    }
}

/// A charge in a uniform magnetic field (symmetric gauge): a velocity-dependent potential.
pub(crate) struct Charge {
    pub coordinates: [Coordinate; 2],
    pub m: f64,
    pub e_b: f64,
}

impl Charge {
    /// Mass `m`, charge times field `e_b`, in the plane `(x, y)`.
    pub(crate) fn new(m: f64, e_b: f64) -> Self {
        Self { coordinates: [Coordinate::length("x"), Coordinate::length("y")], m, e_b }
    }
}

impl Lagrangian for Charge {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }
    fn lagrangian<S: Scalar>(&self, _t: S, q: &[S], v: &[S]) -> S {
        (v[0] * v[0] + v[1] * v[1]) * (0.5 * self.m) + (q[0] * v[1] - q[1] * v[0]) * (0.5 * self.e_b)
    }
}

/// `|got − expected| ≤ rtol · max(|expected|, 1)`: relative, or absolute below 1.
#[track_caller]
pub(crate) fn assert_relative(got: f64, expected: f64, rtol: f64) {
    assert!((got - expected).abs() <= rtol * expected.abs().max(1.0), "{got} vs {expected}");
}

/// The seeded generator of every check (the validation library's), with `range(a, b)` uniform
/// in `[a, b)`.
pub(crate) use lagrange_testing::{Rng, rng};

/// Uniform samples in `[a, b)`.
pub(crate) trait Range {
    /// Uniform in `[a, b)`.
    fn range(&mut self, a: f64, b: f64) -> f64;
}

impl Range for Rng {
    fn range(&mut self, a: f64, b: f64) -> f64 {
        use rand::Rng as _;
        self.random_range(a..b)
    }
}

/// A hanging chain of uniform rods with their own masses and lengths, absolute angles from the
/// downward vertical, poses written by hand (as the scenes do), declaring its [`Tree`].
#[derive(Clone, Debug)]
pub(crate) struct RodChain {
    pub description: Description,
    pub lengths: Vec<f64>,
    pub tree: crate::Tree,
}

impl RodChain {
    pub(crate) fn new(masses: &[f64], lengths: &[f64], g: f64) -> Self {
        use crate::tree::{Joint, Parent};
        let bodies: Vec<Body> = masses
            .iter()
            .zip(lengths)
            .enumerate()
            .map(|(i, (&m, &l))| Body::rigid(format!("rod {i}"), m, m * l * l / 12.0))
            .collect();
        let joints = lengths
            .iter()
            .enumerate()
            .map(|(i, &l)| match i {
                0 => Joint::absolute_revolute("θ0", Parent::Ground, [0.0, 0.0], [0.0, 0.5 * l]),
                _ => Joint::absolute_revolute(
                    format!("θ{i}"),
                    Parent::Body(i - 1),
                    [0.0, -0.5 * lengths[i - 1]],
                    [0.0, 0.5 * l],
                ),
            })
            .collect();
        let tree = crate::Tree::new(joints, bodies.clone(), g).expect("valid tree");
        let coordinates = (0..masses.len()).map(|i| Coordinate::angle(format!("θ{i}"))).collect();
        let description = Description { coordinates, bodies, gravity: g, ..Description::default() };
        Self { description, lengths: lengths.to_vec(), tree }
    }
}

impl Mechanism for RodChain {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        let (mut x, mut y) = (S::zero(), S::zero());
        for ((pose, &theta), &l) in p.iter_mut().zip(q).zip(&self.lengths) {
            let (sin, cos) = theta.sin_cos();
            *pose = Pose::new(x + sin * (0.5 * l), y - cos * (0.5 * l), theta);
            x += sin * l;
            y -= cos * l;
        }
    }
    fn tree(&self) -> Option<&crate::Tree> {
        Some(&self.tree)
    }
}

/// A pendulum (point bob `m` on a rod `r`) whose pivot is driven horizontally,
/// `x_p = A sin(ω t)`, with a torsional spring `V = ½ k θ²` and viscous damping `Q = −c θ̇`:
/// every optional term at once (time-dependent poses, a potential, a velocity-dependent force),
#[derive(Clone, Debug)]
pub(crate) struct Driven {
    pub description: Description,
    pub m: f64,
    pub r: f64,
    pub amplitude: f64,
    pub omega: f64,
    pub k: f64,
    pub c: f64,
}

/// The driven pendulum with its defaults ([`Driven::new`]).
pub(crate) fn driven() -> Driven {
    Driven::new()
}

impl Driven {
    pub(crate) fn new() -> Self {
        let m = 0.7;
        let description = Description::new().angle("θ").point("bob", m).gravity(9.81);
        Self { description, m, r: 1.3, amplitude: 0.2, omega: 2.5, k: 3.0, c: 0.4 }
    }
}

impl Mechanism for Driven {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, t: S, q: &[S], p: &mut [Pose<S>]) {
        let pivot = (t * self.omega).sin() * self.amplitude;
        p[0] = Pose::point(pivot + q[0].sin() * self.r, -q[0].cos() * self.r);
    }
    fn potential<S: Scalar>(&self, _t: S, q: &[S], _p: &[Pose<S>]) -> Option<S> {
        Some(q[0] * q[0] * (0.5 * self.k))
    }
    fn generalized_force<S: Scalar>(&self, _t: S, _q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        force[0] -= qdot[0] * self.c;
        true
    }
}
