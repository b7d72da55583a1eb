//! Hand-coded kinematics and dynamics of planar linkages whose points are sums of rotating
//! arms, for the closed forms of the closed-loop scenes (no automatic differentiation, no
//! engine): every point is `p = p₀ + Σ_a R(α_a) r_a + Σ_j q_j v_j` with each arm's angle
//! `α_a = k_a · q` linear in the coordinates, so that its velocity is `J q̇` with
//! `J_{:,j} = Σ_a k_{a,j} R(α_a + π/2) r_a + v_j` and its convective acceleration (at `q̈ = 0`)
//! is `−Σ_a (k_a · q̇)² R(α_a) r_a`. Body angles are linear in `q` too. The equations of motion
//! `M q̈ + Gᵀ λ = f`, `G q̈ = −γ` are then assembled from the bodies and the loop-closure points
//! and solved as one dense KKT system.

use nalgebra::{DMatrix, DVector};

/// An arm `R(k · q) r` of a point.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Arm {
    /// `k`: the arm's angle is `k · q`.
    pub(crate) k: Vec<f64>,
    /// `r`: the arm at angle 0.
    pub(crate) r: [f64; 2],
}

/// A point of the linkage as a function of `q`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Point {
    /// `p₀`.
    pub(crate) fixed: [f64; 2],
    /// The rotating arms.
    pub(crate) arms: Vec<Arm>,
    /// `(j, v_j)`: the point moves by `q_j v_j` (a slider).
    pub(crate) linear: Vec<(usize, [f64; 2])>,
}

/// A point's position, Jacobian rows (`x` then `y`, `n` entries each) and convective
/// acceleration at `(q, q̇)`.
pub(crate) struct Motion {
    pub(crate) position: [f64; 2],
    pub(crate) jacobian: [Vec<f64>; 2],
    pub(crate) convective: [f64; 2],
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Point {
    /// The fixed point `p₀`.
    pub(crate) fn at(x: f64, y: f64) -> Self {
        Self { fixed: [x, y], arms: Vec::new(), linear: Vec::new() }
    }

    /// Add the arm `R(k · q) r`.
    pub(crate) fn arm(mut self, k: &[f64], r: [f64; 2]) -> Self {
        self.arms.push(Arm { k: k.to_vec(), r });
        self
    }

    /// Add `q_j v`.
    pub(crate) fn slide(mut self, j: usize, v: [f64; 2]) -> Self {
        self.linear.push((j, v));
        self
    }

    /// Position, Jacobian and convective acceleration at `(q, q̇)`.
    pub(crate) fn motion(&self, q: &[f64], qdot: &[f64]) -> Motion {
        let n = q.len();
        let mut position = self.fixed;
        let mut jacobian = [vec![0.0; n], vec![0.0; n]];
        let mut convective = [0.0; 2];
        for arm in &self.arms {
            let (s, c) = dot(&arm.k, q).sin_cos();
            let rotated = [c * arm.r[0] - s * arm.r[1], s * arm.r[0] + c * arm.r[1]];
            let rate = dot(&arm.k, qdot);
            for i in 0..2 {
                position[i] += rotated[i];
                convective[i] -= rate * rate * rotated[i];
            }
            for (j, &k) in arm.k.iter().enumerate() {
                jacobian[0][j] -= k * rotated[1];
                jacobian[1][j] += k * rotated[0];
            }
        }
        for &(j, v) in &self.linear {
            for i in 0..2 {
                position[i] += q[j] * v[i];
                jacobian[i][j] += v[i];
            }
        }
        Motion { position, jacobian, convective }
    }
}

/// A rigid body of the linkage.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LinkBody {
    /// Mass (kg).
    pub(crate) mass: f64,
    /// Inertia about the centre of mass (kg m²).
    pub(crate) inertia: f64,
    /// The centre of mass.
    pub(crate) centre: Point,
    /// The body's angle is `angle · q` (plus a constant).
    pub(crate) angle: Vec<f64>,
}

/// A linkage: bodies, gravity, loop-closure rows (each a point that must stay at the origin,
/// two rows), a constant torque on the angle `k · q`, and a linear spring between a fixed point
/// and a moving one.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Linkage {
    pub(crate) bodies: Vec<LinkBody>,
    pub(crate) gravity: f64,
    pub(crate) loops: Vec<Point>,
    /// `(k, τ)`: generalized force `τ k`.
    pub(crate) torque: (Vec<f64>, f64),
    /// `(fixed end, moving end, stiffness, natural length)`.
    pub(crate) spring: Option<([f64; 2], Point, f64, f64)>,
}

impl Linkage {
    /// `T + V` (gravity and spring) `− τ k·q` at `(q, q̇)`: the conserved energy function with
    /// a constant torque.
    pub(crate) fn energy(&self, q: &[f64], qdot: &[f64]) -> f64 {
        let mut energy = 0.0;
        for body in &self.bodies {
            let motion = body.centre.motion(q, qdot);
            let v = [dot(&motion.jacobian[0], qdot), dot(&motion.jacobian[1], qdot)];
            let omega = dot(&body.angle, qdot);
            energy += 0.5 * body.mass * (v[0] * v[0] + v[1] * v[1]) + 0.5 * body.inertia * omega * omega;
            energy += body.mass * self.gravity * motion.position[1];
        }
        if let Some((fixed, point, stiffness, natural)) = &self.spring {
            let p = point.motion(q, qdot).position;
            let length = (p[0] - fixed[0]).hypot(p[1] - fixed[1]);
            energy += 0.5 * stiffness * (length - natural) * (length - natural);
        }
        energy - self.torque.1 * dot(&self.torque.0, q)
    }

    /// `(q̈, λ)` from `M q̈ + Gᵀ λ = f`, `G q̈ = −γ` (one dense LU with partial pivoting of the
    /// KKT matrix); `None` if it is singular.
    pub(crate) fn accelerations(&self, q: &[f64], qdot: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
        let n = q.len();
        let m = 2 * self.loops.len();
        let mut kkt = DMatrix::<f64>::zeros(n + m, n + m);
        let mut rhs = DVector::<f64>::zeros(n + m);
        for body in &self.bodies {
            let motion = body.centre.motion(q, qdot);
            for i in 0..n {
                for j in 0..n {
                    let translation = dot(
                        &[motion.jacobian[0][i], motion.jacobian[1][i]],
                        &[motion.jacobian[0][j], motion.jacobian[1][j]],
                    );
                    kkt[(i, j)] += body.mass * translation + body.inertia * body.angle[i] * body.angle[j];
                }
                rhs[i] -= body.mass
                    * (motion.jacobian[0][i] * motion.convective[0]
                        + motion.jacobian[1][i] * (motion.convective[1] + self.gravity));
            }
        }
        for (i, k) in self.torque.0.iter().enumerate() {
            rhs[i] += self.torque.1 * k;
        }
        if let Some((fixed, point, stiffness, natural)) = &self.spring {
            let motion = point.motion(q, qdot);
            let d = [motion.position[0] - fixed[0], motion.position[1] - fixed[1]];
            let length = d[0].hypot(d[1]);
            let scale = -stiffness * (length - natural) / length;
            for i in 0..n {
                rhs[i] += scale * (d[0] * motion.jacobian[0][i] + d[1] * motion.jacobian[1][i]);
            }
        }
        for (l, point) in self.loops.iter().enumerate() {
            let motion = point.motion(q, qdot);
            for c in 0..2 {
                let row = n + 2 * l + c;
                for j in 0..n {
                    kkt[(row, j)] = motion.jacobian[c][j];
                    kkt[(j, row)] = motion.jacobian[c][j];
                }
                rhs[row] = -motion.convective[c];
            }
        }
        let solution = kkt.lu().solve(&rhs)?;
        if solution.iter().any(|v| !v.is_finite()) {
            return None;
        }
        Some((solution.rows(0, n).iter().copied().collect(), solution.rows(n, m).iter().copied().collect()))
    }

    /// The loop-closure residuals `Φ(q)` and their rates `G q̇`.
    pub(crate) fn residuals(&self, q: &[f64], qdot: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let (mut phi, mut rate) = (Vec::new(), Vec::new());
        for point in &self.loops {
            let motion = point.motion(q, qdot);
            for c in 0..2 {
                phi.push(motion.position[c]);
                rate.push(dot(&motion.jacobian[c], qdot));
            }
        }
        (phi, rate)
    }
}

/// Solve the 2×2 system `[[a, b], [c, d]] x = (e, f)` by Cramer's rule.
pub(crate) fn solve2(a: f64, b: f64, c: f64, d: f64, e: f64, f: f64) -> [f64; 2] {
    let det = a * d - b * c;
    [(e * d - b * f) / det, (a * f - e * c) / det]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pendulum of one arm: position, Jacobian and convective term by hand.
    #[test]
    fn one_arm_is_a_pendulum() {
        let p = Point::at(1.0, 0.0).arm(&[1.0], [2.0, 0.0]);
        let m = p.motion(&[0.5], &[3.0]);
        let (s, c) = 0.5_f64.sin_cos();
        assert_eq!(m.position, [1.0 + 2.0 * c, 2.0 * s]);
        assert_eq!(m.jacobian, [vec![-2.0 * s], vec![2.0 * c]]);
        assert_eq!(m.convective, [-9.0 * 2.0 * c, -9.0 * 2.0 * s]);
    }
}
