//! Andrews' squeezing mechanism in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Anchor, Constraint, pin};
use crate::cartesian::system::AppliedForce;
use crate::rapier::scenes::Draft;
use lagrange::{Scalar, State};
use lagrange_scenes::AndrewsSqueezer;

impl MaximalScene for AndrewsSqueezer {
    /// `β`, `Θ`, `γ`, `Φ`, `δ`, `Ω`, `ε` from the bodies' angles `β`, `β + Θ`, `γ`, `Φ + δ`, `δ`,
    /// `Ω + ε`, `ε`.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![z[0][2], z[1][2] - z[0][2], z[2][2], z[3][2] - z[4][2], z[4][2], z[5][2] - z[6][2], z[6][2]]
    }

    /// Ten pins (20 equations on 21 body coordinates), at the joint points in each body's
    /// frame (origin at its centre of mass; docs/scenes.md#andrews_squeezer): K1 at O, K1–K2 at
    /// P1, K3 at B, K2–K3, K2–K4 and K2–K6 at E, K5 at A, K4–K5 at G, K7 at A, K6–K7 at H.
    fn constraints(&self, _names: &[String]) -> Vec<Constraint> {
        let s = self;
        let e_on_k2 = || Anchor::on(1, s.da - s.d, 0.0);
        let a = || Anchor::World { x: s.xa, y: s.ya };
        vec![
            pin(Anchor::on(0, -s.ra, 0.0), Anchor::ORIGIN, "K1 at O".into()),
            pin(Anchor::on(0, s.rr - s.ra, 0.0), Anchor::on(1, s.da, 0.0), "K1–K2 at P1".into()),
            pin(Anchor::on(2, -s.sa, s.sb), Anchor::World { x: s.xb, y: s.yb }, "K3 at B".into()),
            pin(e_on_k2(), Anchor::on(2, -s.sa, s.sb - s.ss), "K2–K3 at E".into()),
            pin(e_on_k2(), Anchor::on(3, 0.0, -s.ea), "K2–K4 at E".into()),
            pin(e_on_k2(), Anchor::on(5, s.fa, 0.0), "K2–K6 at E".into()),
            pin(Anchor::on(4, -s.ta, s.tb), a(), "K5 at A".into()),
            pin(Anchor::on(3, 0.0, s.e - s.ea), Anchor::on(4, s.zt - s.ta, s.tb), "K4–K5 at G".into()),
            pin(Anchor::on(6, -s.ua, s.ub), a(), "K7 at A".into()),
            pin(Anchor::on(5, -(s.zf - s.fa), 0.0), Anchor::on(6, -s.ua, s.ub - s.u), "K6–K7 at H".into()),
        ]
    }

    /// The driving torque `mom` on K1 (the spring acts through the scene's potential).
    fn applied_force(&self) -> AppliedForce {
        if self.mom != 0.0 { AppliedForce::Torque { body: 0, torque: self.mom } } else { AppliedForce::None }
    }

    /// The ten pins as revolute joints at the joint points in each body's frame
    /// (docs/rapier.md#loops). Impulse joints: all ten. Multibody joints: the spanning tree
    /// ground → K1 (O) → K2 (P1), ground → K3 (B), ground → K5 (A) → K4 (G), ground → K7 (A) → K6
    /// (H), and the three pins at `E` (K2–K3, K2–K4, K2–K6) as loop-closing impulse joints. Each
    /// step: the spring `C`–`D` on K3 and the torque `mom` on K1.
    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let s = self;
        let ground = draft.ground();
        let k: Vec<usize> = (0..7).map(|b| draft.reduced(b)).collect();
        let (a, e_on_k2) = ([s.xa, s.ya], [s.da - s.d, 0.0]);
        draft.revolute(ground, k[0], [0.0, 0.0], [-s.ra, 0.0]);
        draft.revolute(k[0], k[1], [s.rr - s.ra, 0.0], [s.da, 0.0]);
        draft.revolute(ground, k[2], [s.xb, s.yb], [-s.sa, s.sb]);
        draft.revolute(ground, k[4], a, [-s.ta, s.tb]);
        draft.revolute(k[4], k[3], [s.zt - s.ta, s.tb], [0.0, s.e - s.ea]);
        draft.revolute(ground, k[6], a, [-s.ua, s.ub]);
        draft.revolute(k[6], k[5], [-s.ua, s.ub - s.u], [-(s.zf - s.fa), 0.0]);
        for (body, anchor) in [(k[2], [-s.sa, s.sb - s.ss]), (k[3], [0.0, -s.ea]), (k[5], [s.fa, 0.0])] {
            let closing = draft.revolute(k[1], body, e_on_k2, anchor);
            draft.close_loop(closing);
        }
        draft.spring(k[2], [s.sd - s.sa, s.sb - s.sc], [s.xc, s.yc], s.c0, s.l0);
        draft.torque(k[0], s.mom);
    }
}
