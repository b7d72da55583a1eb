//! Deterministic probe states at which the engine checks a mechanism's structure once.

use crate::LagrangianFunction;
use num_dual::Dual64;

/// A few fixed, generic states `(q, q̇, t)`: away from 0 and from special angles, so that an
/// identity that holds at all of them holds structurally (it is evaluated exactly by AD).
pub(crate) struct ProbeStates {
    n: usize,
    q: Vec<f64>,
    qdot: Vec<f64>,
    t: Vec<f64>,
}

const PROBES: usize = 3;

impl ProbeStates {
    pub(crate) fn new(n: usize) -> Self {
        // splitmix64: a fixed, portable sequence.
        let mut seed: u64 = 0x5EED_1A6A_A6E0_0001;
        let mut next = move || {
            seed = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = seed;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let q = (0..PROBES * n).map(|_| 0.35 + 0.5 * next()).collect();
        let qdot = (0..PROBES * n).map(|_| 0.8 * next() - 0.4).collect();
        let t = (0..PROBES).map(|_| 0.1 + next()).collect();
        Self { n, q, qdot, t }
    }

    pub(crate) fn len(&self) -> usize {
        PROBES
    }

    /// Probe state `k`: `(q, q̇, t)`.
    pub(crate) fn state(&self, k: usize) -> (&[f64], &[f64], f64) {
        let r = k * self.n..(k + 1) * self.n;
        (&self.q[r.clone()], &self.qdot[r], self.t[k])
    }

    /// Which coordinates are cyclic (`∂L/∂q_j` exactly zero at every probe), and whether the
    /// Lagrangian is autonomous (`∂L/∂t` exactly zero at every probe).
    pub(crate) fn lagrangian_structure<F: LagrangianFunction>(&self, f: &F) -> (Vec<bool>, bool) {
        let n = self.n;
        let mut scratch = f.scratch::<Dual64>();
        let mut q = vec![Dual64::from(0.0); n];
        let mut qdot = vec![Dual64::from(0.0); n];
        let mut cyclic = vec![true; n];
        let mut autonomous = true;
        for k in 0..PROBES {
            let (q0, qdot0, t0) = self.state(k);
            for (d, v) in qdot.iter_mut().zip(qdot0) {
                *d = Dual64::from(*v);
            }
            for j in 0..n {
                for (i, (d, v)) in q.iter_mut().zip(q0).enumerate() {
                    *d = Dual64::new(*v, if i == j { 1.0 } else { 0.0 });
                }
                let l = f.lagrangian_with(&mut scratch, Dual64::from(t0), &q, &qdot);
                cyclic[j] &= l.eps == 0.0;
            }
            for (d, v) in q.iter_mut().zip(q0) {
                *d = Dual64::from(*v);
            }
            let l = f.lagrangian_with(&mut scratch, Dual64::new(t0, 1.0), &q, &qdot);
            autonomous &= l.eps == 0.0;
        }
        (cyclic, autonomous)
    }
}
