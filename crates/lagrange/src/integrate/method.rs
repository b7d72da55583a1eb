//! Which integrator to run, with its setting: [`Method`], its kinds ([`MethodKind`], the one
//! list of the methods that the CLI and the reports reuse), and their text forms.

use super::Tolerances;
use std::fmt;
use std::str::FromStr;

/// Which integrator, with its step or tolerances.
///
/// Its text form is the kind's name with the setting after a colon: `rk4:0.001` (the step),
/// `dopri5:1e-10` (one tolerance, relative and absolute) or `dopri5:1e-10,1e-12` (relative,
/// absolute). [`FromStr`] reads it back exactly, also reads a name alone with the
/// [default setting](MethodKind::default_method), and reads the former names
/// ([`MethodKind::FORMER_NAMES`]) too.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Classical RK4 with fixed step `dt`.
    Rk4 {
        /// Step.
        dt: f64,
    },
    /// Dormand–Prince 5(4) with error control.
    Dopri5 {
        /// Tolerances.
        tol: Tolerances,
    },
    /// Dormand–Prince 8(5,3) ([`Dop853`](super::Dop853)) with error control, for tight
    /// tolerances.
    Dop853 {
        /// Tolerances.
        tol: Tolerances,
    },
    /// Variational midpoint (discrete Euler–Lagrange) with fixed step `dt`.
    Variational {
        /// Step.
        dt: f64,
    },
    /// L-stable SDIRK4 ([`Sdirk4`](super::Sdirk4)) with error control, for stiff problems.
    Sdirk4 {
        /// Tolerances.
        tol: Tolerances,
    },
    /// Gauss–Legendre of order 4 ([`Gauss4`](super::Gauss4)), symplectic, with fixed step `dt`.
    Gauss4 {
        /// Step.
        dt: f64,
    },
}

/// The kind of a [`Method`], without its setting.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MethodKind {
    /// [`Method::Rk4`].
    Rk4,
    /// [`Method::Dopri5`].
    Dopri5,
    /// [`Method::Dop853`].
    Dop853,
    /// [`Method::Variational`].
    Variational,
    /// [`Method::Sdirk4`].
    Sdirk4,
    /// [`Method::Gauss4`].
    Gauss4,
}

impl MethodKind {
    /// Every kind, in the order the CLI lists them.
    pub const ALL: [MethodKind; 6] = [
        MethodKind::Rk4,
        MethodKind::Dopri5,
        MethodKind::Dop853,
        MethodKind::Variational,
        MethodKind::Sdirk4,
        MethodKind::Gauss4,
    ];

    /// Short name, as the CLI spells it and the reports print it: the algorithm's, `rk4`,
    /// `dopri5`, `dop853`, `variational`, `sdirk4`, `gauss4`.
    pub const fn name(self) -> &'static str {
        match self {
            MethodKind::Rk4 => "rk4",
            MethodKind::Dopri5 => "dopri5",
            MethodKind::Dop853 => "dop853",
            MethodKind::Variational => "variational",
            MethodKind::Sdirk4 => "sdirk4",
            MethodKind::Gauss4 => "gauss4",
        }
    }

    /// The names three methods had before they were named by their algorithm (`adaptive`,
    /// `implicit`, `gauss`), which [`FromStr`] and the CLI still read.
    pub const FORMER_NAMES: [(&'static str, MethodKind); 3] =
        [("adaptive", MethodKind::Dopri5), ("implicit", MethodKind::Sdirk4), ("gauss", MethodKind::Gauss4)];

    /// One line on the method and its setting (help texts).
    pub const fn summary(self) -> &'static str {
        match self {
            MethodKind::Rk4 => "Classical RK4, fixed step `--dt`",
            MethodKind::Dopri5 => "Dormand–Prince 5(4) with error control `--tol` and dense output",
            MethodKind::Dop853 => {
                "Dormand–Prince 8(5,3) (DOP853) with error control `--tol` and dense output, for tolerances of 1e-10 and below"
            }
            MethodKind::Variational => "Variational midpoint (discrete Euler–Lagrange), fixed step `--dt`",
            MethodKind::Sdirk4 => "L-stable implicit SDIRK4 with error control `--tol`, for stiff problems",
            MethodKind::Gauss4 => "Gauss–Legendre of order 4 (implicit, symplectic), fixed step `--dt`",
        }
    }

    /// Whether the method takes a fixed step (otherwise tolerances).
    pub const fn is_fixed_step(self) -> bool {
        matches!(self, MethodKind::Rk4 | MethodKind::Variational | MethodKind::Gauss4)
    }

    /// The method of this kind with `setting`: the step of a fixed-step method, or else the
    /// tolerance (relative and absolute).
    pub fn with(self, setting: f64) -> Method {
        let tol = Tolerances::uniform(setting);
        match self {
            MethodKind::Rk4 => Method::Rk4 { dt: setting },
            MethodKind::Dopri5 => Method::Dopri5 { tol },
            MethodKind::Dop853 => Method::Dop853 { tol },
            MethodKind::Variational => Method::Variational { dt: setting },
            MethodKind::Sdirk4 => Method::Sdirk4 { tol },
            MethodKind::Gauss4 => Method::Gauss4 { dt: setting },
        }
    }

    /// The method with its default setting: a step of `1e-3`; a tolerance of `1e-10` for
    /// [`Adaptive`](MethodKind::Dopri5), `1e-12` for [`Dop853`](MethodKind::Dop853) and `1e-8`
    /// for [`Implicit`](MethodKind::Sdirk4).
    pub fn default_method(self) -> Method {
        match self {
            MethodKind::Dopri5 => self.with(1e-10),
            MethodKind::Dop853 => self.with(1e-12),
            MethodKind::Sdirk4 => self.with(1e-8),
            _ => self.with(1e-3),
        }
    }
}

impl Method {
    /// The kind, without the setting.
    pub fn kind(&self) -> MethodKind {
        match self {
            Method::Rk4 { .. } => MethodKind::Rk4,
            Method::Dopri5 { .. } => MethodKind::Dopri5,
            Method::Dop853 { .. } => MethodKind::Dop853,
            Method::Variational { .. } => MethodKind::Variational,
            Method::Sdirk4 { .. } => MethodKind::Sdirk4,
            Method::Gauss4 { .. } => MethodKind::Gauss4,
        }
    }

    /// Short name: `rk4`, `dopri5`, `dop853`, `variational`, `sdirk4`, `gauss4`.
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }

    /// The method with its setting, as messages name a run: `rk4 at dt = 1e-3`,
    /// `dopri5 at tol = 1e-10`.
    pub fn describe(&self) -> String {
        match *self {
            Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss4 { dt } => {
                format!("{} at dt = {dt:e}", self.name())
            }
            Method::Dopri5 { tol } | Method::Dop853 { tol } | Method::Sdirk4 { tol } => {
                format!("{} at tol = {:e}", self.name(), tol.rtol)
            }
        }
    }
}

/// A method name or setting that does not parse.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseMethodError {
    /// The text.
    pub text: String,
    /// What is wrong with it.
    pub why: String,
}

impl fmt::Display for ParseMethodError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}` is not a method: {}", self.text, self.why)
    }
}

impl std::error::Error for ParseMethodError {}

impl fmt::Display for MethodKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for MethodKind {
    type Err = ParseMethodError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let former = MethodKind::FORMER_NAMES.into_iter().find(|(name, _)| *name == text).map(|(_, kind)| kind);
        MethodKind::ALL.into_iter().find(|kind| kind.name() == text).or(former).ok_or_else(|| {
            let names: Vec<&str> = MethodKind::ALL.iter().map(|kind| kind.name()).collect();
            ParseMethodError { text: text.to_string(), why: format!("known methods: {}", names.join(", ")) }
        })
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss4 { dt } => {
                write!(f, "{}:{dt}", self.name())
            }
            Method::Dopri5 { tol } | Method::Dop853 { tol } | Method::Sdirk4 { tol } if tol.rtol == tol.atol => {
                write!(f, "{}:{}", self.name(), tol.rtol)
            }
            Method::Dopri5 { tol } | Method::Dop853 { tol } | Method::Sdirk4 { tol } => {
                write!(f, "{}:{},{}", self.name(), tol.rtol, tol.atol)
            }
        }
    }
}

impl FromStr for Method {
    type Err = ParseMethodError;

    /// `name`, `name:setting`, or for the error-controlled methods `name:rtol,atol`. The values
    /// are not checked here: the integrator rejects a bad step or tolerance with a typed error.
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let error = |why: &str| ParseMethodError { text: text.to_string(), why: why.to_string() };
        let (name, setting) = match text.split_once(':') {
            Some((name, setting)) => (name, Some(setting)),
            None => (text, None),
        };
        let kind: MethodKind = name.parse().map_err(|e: ParseMethodError| error(&e.why))?;
        let Some(setting) = setting else { return Ok(kind.default_method()) };
        let number = |v: &str| v.trim().parse::<f64>().map_err(|_| error(&format!("`{}` is not a number", v.trim())));
        match (kind.is_fixed_step(), setting.split_once(',')) {
            (_, None) => Ok(kind.with(number(setting)?)),
            (false, Some((rtol, atol))) => {
                let tol = Tolerances { rtol: number(rtol)?, atol: number(atol)? };
                Ok(match kind {
                    MethodKind::Dopri5 => Method::Dopri5 { tol },
                    MethodKind::Dop853 => Method::Dop853 { tol },
                    _ => Method::Sdirk4 { tol },
                })
            }
            (true, Some(_)) => Err(error("a fixed-step method takes one step")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every kind parses from its name and prints it; every method reads back from its text
    /// exactly; bad text is a typed error.
    #[test]
    fn methods_parse_and_print() {
        let names: Vec<String> = MethodKind::ALL.iter().map(ToString::to_string).collect();
        assert_eq!(names, ["rk4", "dopri5", "dop853", "variational", "sdirk4", "gauss4"]);
        for kind in MethodKind::ALL {
            assert_eq!(kind.name().parse::<MethodKind>(), Ok(kind));
            assert_eq!(kind.name().parse::<Method>().map(|m| m.kind()), Ok(kind));
            for method in [kind.with(0.1 + 0.2), kind.default_method()] {
                let text = method.to_string();
                assert_eq!(text.parse::<Method>(), Ok(method), "{text}");
            }
        }
        assert_eq!("rk4:0.001".parse::<Method>(), Ok(Method::Rk4 { dt: 1e-3 }));
        let tol = Tolerances { rtol: 1e-10, atol: 1e-12 };
        assert_eq!(Method::Sdirk4 { tol }.to_string(), "sdirk4:0.0000000001,0.000000000001");
        assert_eq!("sdirk4:1e-10,1e-12".parse::<Method>(), Ok(Method::Sdirk4 { tol }));
        // The former names still read, as the same methods.
        assert_eq!("implicit:1e-10,1e-12".parse::<Method>(), Ok(Method::Sdirk4 { tol }));
        assert_eq!("adaptive".parse::<Method>(), Ok(MethodKind::Dopri5.default_method()));
        assert_eq!("gauss:0.01".parse::<Method>(), Ok(Method::Gauss4 { dt: 0.01 }));
        for bad in ["", "rk5", "rk4:", "rk4:x", "gauss4:1,2", "gauss:1,2", "dopri5:1,", "RK4"] {
            assert!(bad.parse::<Method>().is_err(), "{bad}");
        }
    }
}
