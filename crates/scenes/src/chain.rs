//! A hanging chain of `N` uniform rigid links (beyond the lecture).

use crate::params::{GRAVITY, param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, SceneType};
use lagrange::graph::{GROUND, GraphJoint, JointGraph};
use lagrange::tree::{Joint, Parent, Tree};
use lagrange::{Body, Description, Error, Mechanism, Pose, Scalar, State};
use nalgebra::{DMatrix, DVector};

scene_params! {
    /// `N` uniform rods (mass `m`, length `l`, inertia `m l²/12` about the centre) hinged end to end,
    /// the first one to the origin; `q = (θ₁, …, θ_N)`, absolute angles from the downward vertical,
    /// counter-clockwise. With `u(θ) = (sinθ, −cosθ)`: pivot₁ = 0, rod `i`'s centre at
    /// `pivot_i + (l/2) u(θ_i)`, its angle `θ_i`, and `pivot_{i+1} = pivot_i + l u(θ_i)`.
    ///
    /// The chain describes itself as a kinematic [`Tree`] ([`Mechanism::tree`]): rod `i` hangs from
    /// rod `i − 1` (rod 1 from the ground) by a revolute joint whose coordinate is the absolute angle
    /// `θ_i` ([`AngleReference::World`](lagrange::tree::AngleReference)), at `(0, −l/2)` in the rod
    /// above and `(0, l/2)` in its own centre-of-mass frame. So [`Model::new`](lagrange::Model::new) checks the tree against
    /// the poses above and computes `q̈` with the articulated-body algorithm, `O(N)`;
    /// [`Model::new_generic`](lagrange::Model::new_generic) assembles `M` from the poses instead.
    pub struct Chain {
        /// Number of links `N` (1 to 256).
        pub links: usize = ["N", "", 4.0, Domain::Integer { min: 1, max: 256 }, "number of links"],
        /// Mass of each link `m` (kg).
        pub link_mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass of each link"],
        /// Length of each link `l` (m).
        pub link_length: f64 = ["l", "m", 1.0, Domain::Positive, "length of each link"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
    }
    /// A chain of `N` links of mass `m` and length `l` under gravity `g`.
    pub fn new;
    derived {
        // Bodies, coordinates and joints.
        tree: Tree = hanging_rods(&vec![link_mass; links], link_length, gravity)?,
    }
}

/// The tree of [`Chain`] with one mass per rod, top first (the stability suite's chains with
/// link masses spanning 1e6): uniform rods of length `l` and inertia `m_i l²/12`, hinged end to
/// end from the origin, absolute angles `θ₁ … θ_N`.
///
/// # Errors
/// [`Error::InvalidParameter`] from [`Tree::new`]: no rods, a non-finite length or gravity, or a
/// negative or non-finite mass.
pub fn hanging_rods(masses: &[f64], length: f64, gravity: f64) -> Result<Tree, Error> {
    let half = 0.5 * length;
    // Rod i hangs from the bottom end of rod i − 1 (rod 1 from the origin) by its top end.
    let joints = (1..=masses.len())
        .map(|i| {
            let (parent, parent_anchor) =
                if i == 1 { (Parent::Ground, [0.0, 0.0]) } else { (Parent::Body(i - 2), [0.0, -half]) };
            Joint::absolute_revolute(format!("θ{i}"), parent, parent_anchor, [0.0, half])
        })
        .collect();
    let bodies = masses
        .iter()
        .enumerate()
        .map(|(i, &m)| Body::rigid(format!("link {}", i + 1), m, m * length * length / 12.0))
        .collect();
    Tree::new(joints, bodies, gravity)
}

impl Chain {
    /// `S_ij = Σ_k a_ki a_kj` (0-based `i`, `j`), where `a_ki` = 1 if rod `i` is above rod `k`,
    /// ½ if `i = k`, 0 otherwise (rod `k`'s centre is `l Σ_i a_ki u(θ_i)`): rods `k ≥ max(i, j)`
    /// contribute, so `S_ij = N − max(i, j) − ½` for `i ≠ j` and `S_ii = N − i − ¾`.
    fn overlap(&self, i: usize, j: usize) -> f64 {
        let below = (self.links - i.max(j)) as f64;
        if i == j { below - 0.75 } else { below - 0.5 }
    }

    /// The mass matrix `M_ij = m l² (S_ij cos(θ_i − θ_j) + δ_ij/12)` (see
    /// [`closed_form_accelerations`](Self::closed_form_accelerations)).
    fn mass_matrix(&self, q: &[f64]) -> DMatrix<f64> {
        let scale = self.link_mass * self.link_length * self.link_length;
        DMatrix::from_fn(self.links, self.links, |i, j| {
            let diagonal = if i == j { 1.0 / 12.0 } else { 0.0 };
            scale * (self.overlap(i, j) * (q[i] - q[j]).cos() + diagonal)
        })
    }

    /// `q̈` from the hand-derived equations, solved by Cholesky factorization (nalgebra).
    ///
    /// From `T = Σ_k ½ m |ċ_k|² + ½ (m l²/12) θ̇_k²` with `ċ_k = l Σ_i a_ki θ̇_i (cosθ_i, sinθ_i)`
    /// and `V = −m g l Σ_k Σ_i a_ki cosθ_i` (see `overlap` for `a`, `S`), Lagrange's equations are
    /// `Σ_j M_ij θ̈_j = F_i` with
    /// `M_ij = m l² (S_ij cos(θ_i − θ_j) + δ_ij/12)`,
    /// `F_i = −m l² Σ_j S_ij sin(θ_i − θ_j) θ̇_j² − m g l (Σ_k a_ki) sinθ_i`, `Σ_k a_ki = N − i − ½`
    /// (the `∂M/∂θ` terms of `d/dt ∂T/∂θ̇_i − ∂T/∂θ_i` combine into the single `θ̇_j²` sum).
    /// `M` is positive definite for every `q` (a Schur product of two Gram matrices plus
    /// `m l²/12` on the diagonal); for non-finite input the result is NaN.
    ///
    /// # Panics
    /// If `q` or `qdot` does not have `N` entries.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> Vec<f64> {
        let n = self.links;
        assert!(q.len() == n && qdot.len() == n, "q and q̇ must have {n} entries, got {} and {}", q.len(), qdot.len());
        let (m, l, g) = (self.link_mass, self.link_length, self.gravity);
        let scale = m * l * l;
        // Mass matrix and generalized forces.
        let mass_matrix = self.mass_matrix(q);
        let force = DVector::from_fn(n, |i, _| {
            let centrifugal: f64 = (0..n).map(|j| self.overlap(i, j) * (q[i] - q[j]).sin() * qdot[j] * qdot[j]).sum();
            let weight_below = (n - i) as f64 - 0.5;
            -scale * centrifugal - m * g * l * weight_below * q[i].sin()
        });
        // Cholesky solve.
        match mass_matrix.cholesky() {
            Some(factor) => factor.solve(&force).iter().copied().collect(),
            None => vec![f64::NAN; n],
        }
    }
}

impl Mechanism for Chain {
    /// The tree's: its joints' coordinates, its bodies, gravity `g`.
    fn description(&self) -> &Description {
        self.tree.description()
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (length, half) = (self.link_length, 0.5 * self.link_length);
        let (mut pivot_x, mut pivot_y) = (S::zero(), S::zero());
        // Walk down the chain: each rod's centre half a length below its pivot, then the next pivot.
        for (pose, &theta) in world_from_body.iter_mut().zip(q) {
            let (sin, cos) = theta.sin_cos();
            *pose = Pose::new(pivot_x + sin * half, pivot_y - cos * half, theta);
            pivot_x += sin * length;
            pivot_y -= cos * length;
        }
    }

    fn tree(&self) -> Option<&Tree> {
        Some(&self.tree)
    }
}

impl SceneType for Chain {
    const ID: &'static str = "chain";
    const TITLE: &'static str = "Hanging chain of N rigid links";
    const REFERENCE: &'static str = "beyond the lecture; closed form derived in chain.rs";
    param_table!();

    /// Every `θ_i = 0.5`, at rest.
    fn default_state(&self) -> State {
        State::new(0.0, vec![0.5; self.links], vec![0.0; self.links])
    }

    /// The energy `½ q̇ᵀ M q̇ − m g l Σ_i (N − i − ½) cosθ_i` (`M`, `V` as in
    /// [`Chain::closed_form_accelerations`]).
    fn conserves_energy(&self) -> Vec<Conserved> {
        vec![Conserved::energy(self, |s, q, qdot| {
            let qdot = DVector::from_column_slice(qdot);
            let weight = s.link_mass * s.gravity * s.link_length;
            let potential: f64 =
                q.iter().enumerate().map(|(i, theta)| ((s.links - i) as f64 - 0.5) * theta.cos()).sum();
            0.5 * qdot.dot(&(s.mass_matrix(q) * &qdot)) - weight * potential
        })]
    }

    body_scene!();

    /// Rods hinged at their ends: link 1's top `(0, l/2)` at the origin, each link's top at the
    /// previous link's bottom `(0, −l/2)`; absolute angles from the downward vertical.
    fn joint_graph(&self) -> Option<JointGraph> {
        let half = 0.5 * self.link_length;
        let mut graph = crate::scene::graph_of(Self::ID, self);
        let names: Vec<String> = graph.bodies.iter().map(|b| b.name.clone()).collect();
        for (i, name) in names.iter().enumerate() {
            let (parent, anchor) = if i == 0 { (GROUND, [0.0, 0.0]) } else { (names[i - 1].as_str(), [0.0, -half]) };
            let coordinate = self.tree.description().coordinates[i].name.clone();
            graph = graph
                .with_joint(GraphJoint::revolute(coordinate, parent, anchor, name.as_str(), [0.0, half]).absolute());
        }
        Some(graph)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::assert_engine_matches_closed_form;

    /// Five fixed generic states of `n` links (angles and rates from a fixed formula).
    fn states(n: usize) -> Vec<State> {
        let angle = |k: usize, i: usize| 0.5 + 0.9 * ((3 * k + 7 * i) as f64).sin() * if k == 0 { 0.0 } else { 1.0 };
        let rate = |k: usize, i: usize| if k == 0 { 0.0 } else { 1.3 * ((5 * k + 2 * i + 1) as f64).cos() };
        (0..5)
            .map(|k| {
                State::new(
                    k as f64,
                    (0..n).map(|i| angle(k, i)).collect::<Vec<_>>(),
                    (0..n).map(|i| rate(k, i)).collect::<Vec<_>>(),
                )
            })
            .collect()
    }

    #[test]
    fn engine_matches_closed_form_for_several_lengths() {
        let mut params = scene_of::<Chain>().default_params();
        for (links, mass, length) in [(4.0, 1.0, 1.0), (1.0, 2.0, 0.5), (2.0, 0.7, 1.3), (7.0, 1.5, 0.4)] {
            params.set("N", links).unwrap();
            params.set("m", mass).unwrap();
            params.set("l", length).unwrap();
            assert_engine_matches_closed_form(scene_of::<Chain>(), &params, &states(links as usize));
        }
    }

    /// At the largest allowed `N` the mass matrix is no longer well conditioned: its eigenvalues
    /// lie between `m l²/12` and its trace `≈ m l² N²/2`, so `cond(M) ≤ 6 N²` (≈ 4e5 at
    /// N = 256) and both solves carry a relative error up to ~`cond(M)·ε`; the tolerance is
    /// `10 · 6 N² ε` ≈ 9e-10 (observed ≈ 1e-11).
    #[test]
    fn engine_matches_closed_form_for_the_longest_chain() {
        let n = 256;
        let mut params = scene_of::<Chain>().default_params();
        params.set("N", n as f64).unwrap();
        let q: Vec<f64> = (0..n).map(|i| 0.5 + 0.3 * (i as f64).sin()).collect();
        let qdot: Vec<f64> = (0..n).map(|i| 0.2 * (0.7 * i as f64).cos()).collect();
        let mut system = scene_of::<Chain>().build(&params).unwrap();
        let got = system.accelerations(0.0, &q, &qdot).unwrap().to_vec();
        let expected = Chain::from_params(&params).unwrap().closed_form_accelerations(&q, &qdot);
        let tolerance = 10.0 * 6.0 * (n * n) as f64 * f64::EPSILON * crate::testing::max_abs(&expected);
        crate::testing::assert_close("N = 256: engine vs closed form", &expected, &got, tolerance);
    }

    /// The chain runs the articulated-body algorithm, and it agrees with the generic assembly
    /// (`Model::new_generic`, `M` from the same hand-written poses) at every `N` up to 64. The
    /// uniform chain's `cond(M) ≤ 6 N²` (see the longest-chain test) is ≈ 2.5e4 at N = 64, so
    /// each solve carries up to ~`6 N² ε` ≈ 5e-12 relative; the tolerance is 10× that, never
    /// below [`ENGINE_VS_CLOSED_FORM`](crate::testing::ENGINE_VS_CLOSED_FORM).
    #[test]
    fn tree_path_matches_the_generic_path_up_to_64_links() {
        for n in [1, 2, 4, 8, 16, 32, 64] {
            let chain = Chain::new(n, 1.3, 0.7, 9.81).unwrap();
            let tolerance = crate::testing::ENGINE_VS_CLOSED_FORM.max(10.0 * 6.0 * (n * n) as f64 * f64::EPSILON);
            let worst = crate::testing::tree_versus_generic(chain, &states(n)).unwrap();
            assert!(worst <= tolerance, "N = {n}: tree path vs generic path, relative difference {worst:e}");
        }
    }

    /// One link is a physical pendulum: `θ̈ = −(3g/2l) sinθ`.
    #[test]
    fn one_link_is_the_physical_pendulum() {
        let chain = Chain::new(1, 2.0, 0.8, 9.81).unwrap();
        let [alpha] = chain.closed_form_accelerations(&[0.4], &[1.7])[..] else { panic!("one coordinate") };
        let expected = -1.5 * 9.81 / 0.8 * 0.4_f64.sin();
        assert!((alpha - expected).abs() <= 1e-14 * expected.abs(), "expected {expected}, got {alpha}");
    }

    #[test]
    fn link_count_is_validated_and_names_the_coordinates() {
        let chain = Chain::new(3, 1.0, 1.0, 9.81).unwrap();
        let names: Vec<&str> = chain.description().coordinates.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["θ1", "θ2", "θ3"]);
        for links in [0, 257] {
            let result = Chain::new(links, 1.0, 1.0, 9.81);
            assert!(matches!(result, Err(Error::InvalidParameter { ref name, .. }) if name == "links"), "{result:?}");
        }
        assert!(Chain::new(256, 1.0, 1.0, 9.81).is_ok());
        let zero_length = Chain::new(2, 1.0, 0.0, 9.81);
        assert!(matches!(zero_length, Err(Error::InvalidParameter { ref name, .. }) if name == "link_length"));
        assert_eq!(
            Chain::new(2, 1.0, 1.0, 9.81).unwrap().closed_form_accelerations(&[f64::NAN, 0.0], &[0.0, 0.0]).len(),
            2
        );
    }
}
