//! Dormand–Prince 8(5,3) with error control and 7th-order dense output: Hairer's `DOP853`
//! (Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations I*, §II.5 and §II.10;
//! the method of Dormand & Prince 1981 with Hairer's embedded 5th- and 3rd-order error
//! estimates and his dense output).
//!
//! Twelve stages give an 8th-order step, so at tight tolerances it needs far fewer evaluations
//! than [`Dopri5`](super::Dopri5): the method for errors of 1e-10 and below.

use super::control::{Controller, StiffnessWatch, Verdict, first_step, step_toward};
use super::integrator::{Integrator, Stats, check_finite, diverged, rhs};
use super::{Tolerances, check_tolerance};
use crate::{Dynamics, Error, State};

/// Stages of a step.
const STAGES: usize = 12;

/// Stages with the three of the dense output.
const EXTENDED: usize = 16;

/// The nodes `c_i` of the twelve stages and of the three dense-output stages (index 12 is the
/// new point, where the step's last evaluation sits).
// The digits as published with the method.
#[allow(clippy::excessive_precision)]
const C: [f64; EXTENDED] = [
    0.0,
    0.526001519587677318785587544488e-1,
    0.789002279381515978178381316732e-1,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    0.333333333333333333333333333333,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
    1.0,
    0.1,
    0.2,
    0.777777777777777777777777777778,
];

/// The coefficients `a_ij` (row `i` < 16, column `j < i`); row 12 holds the weights `b_j` of the
/// 8th-order solution, rows 13–15 the dense output's extra stages.
// The digits as published with the method.
#[allow(clippy::excessive_precision)]
const A: [[f64; EXTENDED]; EXTENDED] = {
    let mut a = [[0.0; EXTENDED]; EXTENDED];
    a[1][0] = 5.26001519587677318785587544488e-2;
    a[2][0] = 1.97250569845378994544595329183e-2;
    a[2][1] = 5.91751709536136983633785987549e-2;
    a[3][0] = 2.95875854768068491816892993775e-2;
    a[3][2] = 8.87627564304205475450678981324e-2;
    a[4][0] = 2.41365134159266685502369798665e-1;
    a[4][2] = -8.84549479328286085344864962717e-1;
    a[4][3] = 9.24834003261792003115737966543e-1;
    a[5][0] = 3.7037037037037037037037037037e-2;
    a[5][3] = 1.70828608729473871279604482173e-1;
    a[5][4] = 1.25467687566822425016691814123e-1;
    a[6][0] = 3.7109375e-2;
    a[6][3] = 1.70252211019544039314978060272e-1;
    a[6][4] = 6.02165389804559606850219397283e-2;
    a[6][5] = -1.7578125e-2;
    a[7][0] = 3.70920001185047927108779319836e-2;
    a[7][3] = 1.70383925712239993810214054705e-1;
    a[7][4] = 1.07262030446373284651809199168e-1;
    a[7][5] = -1.53194377486244017527936158236e-2;
    a[7][6] = 8.27378916381402288758473766002e-3;
    a[8][0] = 6.24110958716075717114429577812e-1;
    a[8][3] = -3.36089262944694129406857109825;
    a[8][4] = -8.68219346841726006818189891453e-1;
    a[8][5] = 2.75920996994467083049415600797e1;
    a[8][6] = 2.01540675504778934086186788979e1;
    a[8][7] = -4.34898841810699588477366255144e1;
    a[9][0] = 4.77662536438264365890433908527e-1;
    a[9][3] = -2.48811461997166764192642586468;
    a[9][4] = -5.90290826836842996371446475743e-1;
    a[9][5] = 2.12300514481811942347288949897e1;
    a[9][6] = 1.52792336328824235832596922938e1;
    a[9][7] = -3.32882109689848629194453265587e1;
    a[9][8] = -2.03312017085086261358222928593e-2;
    a[10][0] = -9.3714243008598732571704021658e-1;
    a[10][3] = 5.18637242884406370830023853209;
    a[10][4] = 1.09143734899672957818500254654;
    a[10][5] = -8.14978701074692612513997267357;
    a[10][6] = -1.85200656599969598641566180701e1;
    a[10][7] = 2.27394870993505042818970056734e1;
    a[10][8] = 2.49360555267965238987089396762;
    a[10][9] = -3.0467644718982195003823669022;
    a[11][0] = 2.27331014751653820792359768449;
    a[11][3] = -1.05344954667372501984066689879e1;
    a[11][4] = -2.00087205822486249909675718444;
    a[11][5] = -1.79589318631187989172765950534e1;
    a[11][6] = 2.79488845294199600508499808837e1;
    a[11][7] = -2.85899827713502369474065508674;
    a[11][8] = -8.87285693353062954433549289258;
    a[11][9] = 1.23605671757943030647266201528e1;
    a[11][10] = 6.43392746015763530355970484046e-1;
    a[12][0] = 5.42937341165687622380535766363e-2;
    a[12][5] = 4.45031289275240888144113950566;
    a[12][6] = 1.89151789931450038304281599044;
    a[12][7] = -5.8012039600105847814672114227;
    a[12][8] = 3.1116436695781989440891606237e-1;
    a[12][9] = -1.52160949662516078556178806805e-1;
    a[12][10] = 2.01365400804030348374776537501e-1;
    a[12][11] = 4.47106157277725905176885569043e-2;
    a[13][0] = 5.61675022830479523392909219681e-2;
    a[13][6] = 2.53500210216624811088794765333e-1;
    a[13][7] = -2.46239037470802489917441475441e-1;
    a[13][8] = -1.24191423263816360469010140626e-1;
    a[13][9] = 1.5329179827876569731206322685e-1;
    a[13][10] = 8.20105229563468988491666602057e-3;
    a[13][11] = 7.56789766054569976138603589584e-3;
    a[13][12] = -8.298e-3;
    a[14][0] = 3.18346481635021405060768473261e-2;
    a[14][5] = 2.83009096723667755288322961402e-2;
    a[14][6] = 5.35419883074385676223797384372e-2;
    a[14][7] = -5.49237485713909884646569340306e-2;
    a[14][10] = -1.08347328697249322858509316994e-4;
    a[14][11] = 3.82571090835658412954920192323e-4;
    a[14][12] = -3.40465008687404560802977114492e-4;
    a[14][13] = 1.41312443674632500278074618366e-1;
    a[15][0] = -4.28896301583791923408573538692e-1;
    a[15][5] = -4.69762141536116384314449447206;
    a[15][6] = 7.68342119606259904184240953878;
    a[15][7] = 4.06898981839711007970213554331;
    a[15][8] = 3.56727187455281109270669543021e-1;
    a[15][12] = -1.39902416515901462129418009734e-3;
    a[15][13] = 2.9475147891527723389556272149;
    a[15][14] = -9.15095847217987001081870187138;
    a
};

/// The 5th-order error estimate `Σ_j E5_j k_j` (Hairer's `er1 … er12`).
// The digits as published with the method.
#[allow(clippy::excessive_precision)]
const E5: [f64; STAGES] = [
    0.1312004499419488073250102996e-1,
    0.0,
    0.0,
    0.0,
    0.0,
    -0.1225156446376204440720569753e1,
    -0.4957589496572501915214079952,
    0.1664377182454986536961530415e1,
    -0.3503288487499736816886487290,
    0.3341791187130174790297318841,
    0.8192320648511571246570742613e-1,
    -0.2235530786388629525884427845e-1,
];

/// The 3rd-order error estimate `Σ_j E3_j k_j`: the weights `b_j` less Hairer's `bhh1, bhh2,
/// bhh3` on stages 0, 8 and 11.
// The digits as published with the method.
#[allow(clippy::excessive_precision)]
const E3: [f64; STAGES] = {
    let mut e = [0.0; STAGES];
    let mut j = 0;
    while j < STAGES {
        e[j] = A[12][j];
        j += 1;
    }
    e[0] -= 0.244094488188976377952755905512;
    e[8] -= 0.733846688281611857341361741547;
    e[11] -= 0.220588235294117647058823529412e-1;
    e
};

/// The dense output's coefficients `d_4 … d_7` on the sixteen stages (the first three
/// coefficients of the interpolant come from `y₀`, `y₁`, `f₀`, `f₁`).
// The digits as published with the method.
#[allow(clippy::excessive_precision)]
const D: [[f64; EXTENDED]; 4] = {
    let mut d = [[0.0; EXTENDED]; 4];
    d[0][0] = -0.84289382761090128651353491142e1;
    d[0][5] = 0.56671495351937776962531783590;
    d[0][6] = -0.30689499459498916912797304727e1;
    d[0][7] = 0.23846676565120698287728149680e1;
    d[0][8] = 0.21170345824450282767155149946e1;
    d[0][9] = -0.87139158377797299206789907490;
    d[0][10] = 0.22404374302607882758541771650e1;
    d[0][11] = 0.63157877876946881815570249290;
    d[0][12] = -0.88990336451333310820698117400e-1;
    d[0][13] = 0.18148505520854727256656404962e2;
    d[0][14] = -0.91946323924783554000451984436e1;
    d[0][15] = -0.44360363875948939664310572000e1;
    d[1][0] = 0.10427508642579134603413151009e2;
    d[1][5] = 0.24228349177525818288430175319e3;
    d[1][6] = 0.16520045171727028198505394887e3;
    d[1][7] = -0.37454675472269020279518312152e3;
    d[1][8] = -0.22113666853125306036270938578e2;
    d[1][9] = 0.77334326684722638389603898808e1;
    d[1][10] = -0.30674084731089398182061213626e2;
    d[1][11] = -0.93321305264302278729567221706e1;
    d[1][12] = 0.15697238121770843886131091075e2;
    d[1][13] = -0.31139403219565177677282850411e2;
    d[1][14] = -0.93529243588444783865713862664e1;
    d[1][15] = 0.35816841486394083752465898540e2;
    d[2][0] = 0.19985053242002433820987653617e2;
    d[2][5] = -0.38703730874935176555105901742e3;
    d[2][6] = -0.18917813819516756882830838328e3;
    d[2][7] = 0.52780815920542364900561016686e3;
    d[2][8] = -0.11573902539959630126141871134e2;
    d[2][9] = 0.68812326946963000169666922661e1;
    d[2][10] = -0.10006050966910838403183860980e1;
    d[2][11] = 0.77771377980534432092869265740;
    d[2][12] = -0.27782057523535084065932004339e1;
    d[2][13] = -0.60196695231264120758267380846e2;
    d[2][14] = 0.84320405506677161018159903784e2;
    d[2][15] = 0.11992291136182789328035130030e2;
    d[3][0] = -0.25693933462703749003312586129e2;
    d[3][5] = -0.15418974869023643374053993627e3;
    d[3][6] = -0.23152937917604549567536039109e3;
    d[3][7] = 0.35763911791061412378285349910e3;
    d[3][8] = 0.93405324183624310003907691704e2;
    d[3][9] = -0.37458323136451633156875139351e2;
    d[3][10] = 0.10409964950896230045147246184e3;
    d[3][11] = 0.29840293426660503123344363579e2;
    d[3][12] = -0.43533456590011143754432175058e2;
    d[3][13] = 0.96324553959188282948394950600e2;
    d[3][14] = -0.39177261675615439165231486172e2;
    d[3][15] = -0.14972683625798562581422125276e3;
    d
};

/// Step-size control (`DOP853` defaults): exponent 1/8, no PI term, safety 0.9, the step
/// factor bounded to `[1/3, 6]`.
const CONTROL: Controller = Controller::new(1.0 / 8.0, None, 0.9, 1.0 / 3.0, 6.0);

/// Stiffness detection (`DOP853`, Hairer–Wanner I §II.10): `h λ ≈ h ‖f(y₁) − k₁₁‖ / ‖y₁ − Y₁₁‖`
/// (the last stage and the new point both sit at `t + h`); the stability boundary of the method
/// on the negative real axis is about 6.1.
const STIFFNESS: StiffnessWatch = StiffnessWatch::new(6.1);

/// Hairer's `DOP853` on `y = (q, q̇)`: the 8th-order step of Dormand and Prince with an error
/// estimate that combines the embedded 5th- and 3rd-order ones,
/// `err = |h| ‖e₅‖² / √(‖e₅‖² + 0.01 ‖e₃‖²)` (scaled RMS norms, each component by
/// `atol + rtol max(|y_i|, |y'_i|)`), accepted when at most 1; first-same-as-last; dense
/// output of order 7 from three extra stages, evaluated only for a step that an output time
/// falls in. Stiffness is watched as in [`Dopri5`](super::Dopri5).
#[derive(Clone, Debug)]
pub struct Dop853 {
    n: usize,
    tol: Tolerances,
    /// Current time.
    t: f64,
    /// Current state `y = (q, q̇)` (2n).
    y: Vec<f64>,
    /// Stage derivatives `k_0 … k_15` (16 × 2n): after a step, `k_0 … k_11` are its stages and
    /// `k_12 = f(t + h, y₁)`; `k_13 … k_15` the dense-output stages.
    k: [Vec<f64>; EXTENDED],
    /// `f` at the current state (2n): the next step's first stage (the new point's `f` after a
    /// step, re-evaluated after a projection); `k_0` keeps the last step's own first stage for
    /// its dense output until the next step starts.
    f_next: Vec<f64>,
    /// Stage state (2n).
    y_stage: Vec<f64>,
    /// The last step's start `y₀` and end `y₁` (2n each), for the dense output.
    y_old: Vec<f64>,
    y_end: Vec<f64>,
    /// Dense-output coefficients of the last step (7 × 2n), valid when `dense_ready`.
    dense: [Vec<f64>; 7],
    dense_ready: bool,
    /// Start and length of the last accepted step.
    t_old: f64,
    h_old: f64,
    /// Proposed next step.
    h: f64,
    control: Controller,
    /// `h λ` estimate of the last attempted step, and the stiffness test's counts.
    h_lambda: f64,
    stiffness: StiffnessWatch,
    stats: Stats,
}

impl Dop853 {
    /// An integrator for `n` coordinates with the given tolerances.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for non-positive or non-finite tolerances.
    pub fn new(n: usize, tol: Tolerances) -> Result<Self, Error> {
        check_tolerance(tol)?;
        let z = || vec![0.0; 2 * n];
        Ok(Self {
            n,
            tol,
            t: 0.0,
            y: z(),
            k: std::array::from_fn(|_| z()),
            f_next: z(),
            y_stage: z(),
            y_old: z(),
            y_end: z(),
            dense: std::array::from_fn(|_| z()),
            dense_ready: false,
            t_old: 0.0,
            h_old: 0.0,
            h: 0.0,
            control: CONTROL,
            h_lambda: 0.0,
            stiffness: STIFFNESS,
            stats: Stats::default(),
        })
    }

    /// Current time.
    pub fn t(&self) -> f64 {
        self.t
    }

    /// Current coordinates.
    pub fn q(&self) -> &[f64] {
        &self.y[..self.n]
    }

    /// Current velocities.
    pub fn qdot(&self) -> &[f64] {
        &self.y[self.n..]
    }

    /// Work done since [`start`](Self::start) (see [`Stats`]).
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Start at `(t, q, q̇)`: evaluate `f` and choose the first step (Hairer's `HINIT`).
    ///
    /// # Errors
    /// Any error of the equations of motion.
    pub fn start<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        h_max: f64,
    ) -> Result<(), Error> {
        let n = self.n;
        self.t = t;
        self.t_old = t;
        self.h_old = 0.0;
        self.dense_ready = false;
        self.y[..n].copy_from_slice(q);
        self.y[n..].copy_from_slice(qdot);
        self.stats = Stats::default();
        self.control.reset();
        self.stiffness.reset();
        let [k1, ..] = &mut self.k;
        let buffers = [self.f_next.as_mut_slice(), &mut self.y_stage, k1];
        self.h = first_step((system, ws), (self.tol, h_max, 1.0 / 8.0), t, &self.y, buffers, &mut self.stats)?;
        Ok(())
    }

    /// `y_stage = y + h Σ_{j<s} a_sj k_j`.
    fn stage_state(&mut self, s: usize, h: f64) {
        combine(&A[s][..s], &self.k, &self.y, h, &mut self.y_stage);
    }

    /// Take one accepted step, never past `t_limit` (retrying rejected steps internally).
    /// Afterwards [`interpolate`](Self::interpolate) covers `[t_old, t]`.
    ///
    /// # Errors
    /// [`Error::StepSizeUnderflow`] when the step collapses, [`Error::Stiff`] instead once the
    /// stiffness test has fired; any error of the equations of motion.
    pub fn step<D: Dynamics>(&mut self, system: &D, ws: &mut D::Workspace, t_limit: f64) -> Result<(), Error> {
        let (n, n2) = (self.n, 2 * self.n);
        loop {
            let h = step_toward(self.h, self.t, t_limit, &self.stats)?;
            let t = self.t;
            // Stage 0 is f(t, y) (first-same-as-last, or re-evaluated after a projection);
            // stages 1–11.
            self.k[0].copy_from_slice(&self.f_next);
            for s in 1..STAGES {
                self.stage_state(s, h);
                rhs(system, ws, n, t + C[s] * h, &self.y_stage, &mut self.k[s])?;
            }
            // The 8th-order solution y₁ (into y_end) and f(t + h, y₁) (into k_12); stage 11's
            // argument stays in y_stage for the stiffness estimate.
            combine(&A[12][..STAGES], &self.k, &self.y, h, &mut self.y_end);
            rhs(system, ws, n, t + h, &self.y_end, &mut self.k[12])?;
            self.stats.evaluations += STAGES;
            // Error: the 5th- and 3rd-order estimates combined.
            let (mut err5, mut err3, mut num, mut den) = (0.0, 0.0, 0.0, 0.0);
            for i in 0..n2 {
                let (mut e5, mut e3) = (0.0, 0.0);
                for j in 0..STAGES {
                    e5 += E5[j] * self.k[j][i];
                    e3 += E3[j] * self.k[j][i];
                }
                let sk = self.tol.atol + self.tol.rtol * self.y[i].abs().max(self.y_end[i].abs());
                err5 += (e5 / sk).powi(2);
                err3 += (e3 / sk).powi(2);
                num += (self.k[12][i] - self.k[11][i]).powi(2);
                den += (self.y_end[i] - self.y_stage[i]).powi(2);
            }
            let denominator = if err5 + 0.01 * err3 > 0.0 { err5 + 0.01 * err3 } else { 1.0 };
            let err = h.abs() * err5 / (denominator * n2 as f64).sqrt();
            self.h_lambda = StiffnessWatch::h_lambda(h, num, den);
            let h_new = match self.control.judge(err, h) {
                Verdict::Accept(h_new) => h_new,
                Verdict::Reject(h_new) => {
                    self.h = h_new;
                    self.stats.rejected += 1;
                    continue;
                }
            };
            // Accept: keep the step's ends for the dense output, then advance (the new point's
            // f is the next step's first stage).
            self.stiffness.count(self.h_lambda, t, &mut self.stats);
            self.t_old = t;
            self.h_old = h;
            self.t = if h == t_limit - t { t_limit } else { t + h };
            self.y_old.copy_from_slice(&self.y);
            self.y.copy_from_slice(&self.y_end);
            self.f_next.copy_from_slice(&self.k[12]);
            self.dense_ready = false;
            self.h = h_new;
            self.stats.steps += 1;
            return Ok(());
        }
    }

    /// The dense output of the last step: three more stages, then the seven coefficients of the
    /// interpolant.
    fn prepare_dense<D: Dynamics>(&mut self, system: &D, ws: &mut D::Workspace) -> Result<(), Error> {
        let (n, n2, t, h) = (self.n, 2 * self.n, self.t_old, self.h_old);
        for s in 13..EXTENDED {
            combine(&A[s][..s], &self.k, &self.y_old, h, &mut self.y_stage);
            rhs(system, ws, n, t + C[s] * h, &self.y_stage, &mut self.k[s])?;
        }
        self.stats.evaluations += 3;
        for i in 0..n2 {
            let (f0, f1) = (self.k[0][i], self.k[12][i]);
            let delta = self.y_end[i] - self.y_old[i];
            self.dense[0][i] = delta;
            self.dense[1][i] = h * f0 - delta;
            self.dense[2][i] = 2.0 * delta - h * (f1 + f0);
            for (r, row) in D.iter().enumerate() {
                let mut sum = 0.0;
                for j in (0..EXTENDED).filter(|&j| row[j] != 0.0) {
                    sum += row[j] * self.k[j][i];
                }
                self.dense[3 + r][i] = h * sum;
            }
        }
        self.dense_ready = true;
        Ok(())
    }

    /// Dense output at `t` within the last accepted step: `q` and `q̇` (7th order). The first
    /// call within a step evaluates the three extra stages.
    ///
    /// # Errors
    /// Any error of the equations of motion at the extra stages.
    pub fn interpolate<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        t: f64,
        q: &mut [f64],
        qdot: &mut [f64],
    ) -> Result<(), Error> {
        let n = self.n;
        if self.h_old == 0.0 {
            q.copy_from_slice(&self.y[..n]);
            qdot.copy_from_slice(&self.y[n..]);
            return Ok(());
        }
        if !self.dense_ready {
            self.prepare_dense(system, ws)?;
        }
        let theta = (t - self.t_old) / self.h_old;
        let theta1 = 1.0 - theta;
        let d = &self.dense;
        for i in 0..2 * n {
            // y₀ + θ(d₀ + θ₁(d₁ + θ(d₂ + θ₁(d₃ + θ(d₄ + θ₁(d₅ + θ d₆)))))).
            let mut v = d[6][i];
            for (r, row) in d.iter().enumerate().take(6).rev() {
                v = row[i] + if r % 2 == 1 { theta } else { theta1 } * v;
            }
            let v = self.y_old[i] + theta * v;
            if i < n {
                q[i] = v;
            } else {
                qdot[i - n] = v;
            }
        }
        Ok(())
    }
}

/// `out = base + h Σ_j row_j k_j`, over the non-zero entries of `row` (the stages a
/// Runge–Kutta row combines).
fn combine(row: &[f64], k: &[Vec<f64>], base: &[f64], h: f64, out: &mut [f64]) {
    for (i, o) in out.iter_mut().enumerate() {
        let mut sum = 0.0;
        for (j, &a) in row.iter().enumerate().filter(|&(_, &a)| a != 0.0) {
            sum += a * k[j][i];
        }
        *o = base[i] + h * sum;
    }
}

impl<D: Dynamics> Integrator<D> for Dop853 {
    fn begin(&mut self, system: &D, ws: &mut D::Workspace, initial: &State, t_end: f64) -> Result<(), Error> {
        let span = (t_end - initial.t).max(f64::MIN_POSITIVE);
        self.start(system, ws, initial.t, &initial.q, &initial.qdot, span)
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn proposed_step(&self) -> f64 {
        self.h
    }

    fn reached(&self, t_out: f64) -> bool {
        self.t >= t_out
    }

    /// One accepted step toward `t_end` (not `t_out`: [`read`](Integrator::read) interpolates).
    fn advance(&mut self, system: &D, ws: &mut D::Workspace, _: f64, t_end: f64) -> Result<(), Error> {
        let (t, k) = (self.t, self.stats.steps);
        self.step(system, ws, t_end).map_err(|e| diverged(system, e, t, k))?;
        check_finite(system, self.q(), self.qdot(), self.t, self.stats.steps)
    }

    fn read(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        t: f64,
        q: &mut [f64],
        qdot: &mut [f64],
    ) -> Result<(), Error> {
        if t == self.t {
            q.copy_from_slice(Self::q(self));
            qdot.copy_from_slice(Self::qdot(self));
            Ok(())
        } else {
            self.interpolate(system, ws, t, q, qdot)
        }
    }

    fn current(&self) -> (&[f64], &[f64]) {
        (Self::q(self), Self::qdot(self))
    }

    fn project(&mut self, system: &D, ws: &mut D::Workspace) -> Result<(), Error> {
        let n = self.n;
        let (q, qdot) = self.y.split_at_mut(n);
        system.project(ws, self.t, q, qdot)?;
        rhs(system, ws, n, self.t, &self.y, &mut self.f_next)?;
        self.stats.evaluations += 1;
        Ok(())
    }

    fn stats(&self) -> Stats {
        Self::stats(self)
    }
}
