//! Scene parameters: their specifications (name, lecture symbol, unit, default, domain) and a
//! checked set of values.

use lagrange::Error;
use std::fmt;

/// The values a parameter may take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Domain {
    /// Finite and `> 0` (masses, lengths, stiffnesses).
    Positive,
    /// Finite and `≥ 0` (gravity, damping, pulley inertia, massless-allowed pulleys).
    NonNegative,
    /// Any finite value (charges, field strengths, drive amplitudes).
    Finite,
    /// Strictly between the two bounds (the wedge angle, `0 < α < π/2`).
    OpenInterval(f64, f64),
    /// A whole number from `min` to `max` inclusive (the number of links of a chain).
    Integer {
        /// Smallest allowed value.
        min: u32,
        /// Largest allowed value.
        max: u32,
    },
}

impl Domain {
    /// Whether a (finite) value lies in the domain.
    fn contains(self, value: f64) -> bool {
        match self {
            Domain::Positive => value > 0.0,
            Domain::NonNegative => value >= 0.0,
            Domain::Finite => true,
            Domain::OpenInterval(low, high) => low < value && value < high,
            Domain::Integer { min, max } => value.fract() == 0.0 && f64::from(min) <= value && value <= f64::from(max),
        }
    }

    /// What a value must be, as a phrase ("positive", "an integer from 1 to 256").
    fn requirement(self) -> String {
        match self {
            Domain::Positive => "must be positive".into(),
            Domain::NonNegative => "must be non-negative".into(),
            Domain::Finite => "must be finite".into(),
            Domain::OpenInterval(low, high) => format!("must lie strictly between {low} and {high}"),
            Domain::Integer { min, max } => format!("must be an integer from {min} to {max}"),
        }
    }
}

impl fmt::Display for Domain {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Domain::Positive => f.write_str("> 0"),
            Domain::NonNegative => f.write_str("≥ 0"),
            Domain::Finite => f.write_str("finite"),
            Domain::OpenInterval(low, high) => write!(f, "({low}, {high})"),
            Domain::Integer { min, max } => write!(f, "integer in [{min}, {max}]"),
        }
    }
}

/// The specification of one scene parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSpec {
    /// Name in words, as the typed scene's field (`cart_mass`); the key of [`Params`].
    pub name: &'static str,
    /// The symbol docs/scenes.md and the lecture use (`M`, `l'`, `m_p`); also accepted as a key.
    pub symbol: &'static str,
    /// SI unit (`kg`, `m`, `m/s²`; empty for a pure number).
    pub unit: &'static str,
    /// Default value.
    pub default: f64,
    /// Allowed values.
    pub domain: Domain,
    /// One line saying what the parameter is.
    pub description: &'static str,
}

impl ParamSpec {
    /// A specification from its parts (for the scenes' `PARAMS` tables).
    pub(crate) const fn new(
        name: &'static str,
        symbol: &'static str,
        unit: &'static str,
        default: f64,
        domain: Domain,
        description: &'static str,
    ) -> Self {
        Self { name, symbol, unit, default, domain, description }
    }

    /// The symbol spelled in ASCII, also accepted as a key by [`Params::set`]: each Greek letter
    /// by its English name (`α` → `alpha`, `ω` → `omega`, `θ` → `theta`, `λ` → `lambda`,
    /// `μ` → `mu`; `Ω` → `Omega`), every other character kept (`m_p` stays `m_p`).
    pub fn ascii_symbol(&self) -> String {
        ascii_symbol(self.symbol)
    }

    /// Check a value against the domain; non-finite values are always rejected.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the parameter (its [`name`](Self::name)) and saying
    /// what it must be.
    pub fn check(&self, value: f64) -> Result<(), Error> {
        let requirement = if !value.is_finite() {
            "must be finite".to_string()
        } else if !self.domain.contains(value) {
            self.domain.requirement()
        } else {
            return Ok(());
        };
        let unit = if self.unit.is_empty() { String::new() } else { format!(", {}", self.unit) };
        Err(Error::InvalidParameter {
            name: self.name.to_string(),
            value,
            why: format!("{requirement} ({}: {}{unit})", self.symbol, self.description),
        })
    }
}

/// Gravitational acceleration `g` along −y: a parameter of every scene with gravity.
pub(crate) const GRAVITY: ParamSpec =
    ParamSpec::new("gravity", "g", "m/s²", 9.81, Domain::NonNegative, "gravitational acceleration (along −y)");

/// A parameter's value in a typed scene: `f64`, or `usize` for a count (checked as a real
/// number first, so that 2.5 links is an error, not 2).
pub(crate) trait ParamValue: Copy {
    /// The value as the real number the specification checks.
    fn to_f64(self) -> f64;
    /// The value from a real number already checked against its specification.
    fn from_f64(value: f64) -> Self;
}

impl ParamValue for f64 {
    fn to_f64(self) -> f64 {
        self
    }

    fn from_f64(value: f64) -> Self {
        value
    }
}

impl ParamValue for usize {
    fn to_f64(self) -> f64 {
        // usize → f64 is exact up to 2⁵³, far beyond any count a domain allows.
        self as f64
    }

    fn from_f64(value: f64) -> Self {
        // Checked to be a whole number in an `Integer` domain (at most `u32::MAX`).
        value as usize
    }
}

/// Whether two names are equal, in a constant (a shared specification such as [`GRAVITY`] must
/// name the field it fills).
pub(crate) const fn same_name(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// A scene's parameter list, written once: from one row per parameter,
/// `pub field: type = [symbol, unit, default, domain, "description"]` (or `= [SHARED]` for a
/// shared specification such as [`GRAVITY`]), it generates the `PARAMS` table (the field's
/// name is the parameter's name), the struct (`Clone`, `Debug`, `PartialEq`) with the documented
/// public fields and the private derived fields, the validating constructor taking the parameters in the table's order, and
/// `from_table`, the scene from a [`Params`] set (used by [`param_table!`]). The derived fields
/// are computed in order from the parameters (and the derived fields before them), so an
/// expression may use `?`. An optional `finish = path;` after them takes the constructed scene
/// and returns it, completed or refused (`fn(Self) -> Result<Self, Error>`): for what needs the
/// whole scene, such as a linkage's assembly.
macro_rules! scene_params {
    (@spec $field:ident; $shared:ident) => {{
        const _: () = assert!($crate::params::same_name($shared.name, stringify!($field)), "a shared spec names its field");
        $shared
    }};
    (@spec $field:ident; $symbol:literal, $unit:literal, $default:expr, $domain:expr, $description:literal) => {
        $crate::ParamSpec::new(stringify!($field), $symbol, $unit, $default, $domain, $description)
    };
    (
        $(#[doc = $struct_doc:literal])*
        pub struct $scene:ident {
            $(
                $(#[doc = $doc:literal])*
                pub $field:ident : $type:ty = [$($spec:tt)*],
            )*
        }
        $(#[doc = $constructor_doc:literal])*
        $constructor_vis:vis fn $constructor:ident;
        derived {
            $( $derived:ident : $derived_type:ty = $value:expr, )*
        }
        $( finish = $finish:path; )?
    ) => {
        #[doc = concat!("The parameters of [`", stringify!($scene), "`], in order (its public fields).")]
        pub const PARAMS: &[$crate::ParamSpec] = &[$($crate::params::scene_params!(@spec $field; $($spec)*)),*];

        $(#[doc = $struct_doc])*
        ///
        /// Construct with [`new`](Self::new) or [`from_params`](Self::from_params); the fields
        /// are public for reading (changing one afterwards does not update what the engine sees).
        #[derive(Clone, Debug, PartialEq)]
        pub struct $scene {
            $( $(#[doc = $doc])* pub $field: $type, )*
            $( $derived: $derived_type, )*
        }

        impl $scene {
            $(#[doc = $constructor_doc])*
            ///
            /// # Errors
            /// [`Error::InvalidParameter`](lagrange::Error::InvalidParameter) naming the first
            /// parameter outside its domain ([`PARAMS`]).
            // One argument per parameter, in the order of the table that groups them.
            #[allow(clippy::too_many_arguments)]
            $constructor_vis fn $constructor($($field: $type),*) -> Result<Self, ::lagrange::Error> {
                $crate::params::check_all(PARAMS, &[$($crate::params::ParamValue::to_f64($field)),*])?;
                $( let $derived: $derived_type = $value; )*
                let scene = Self { $($field,)* $($derived,)* };
                $( let scene = $finish(scene)?; )?
                Ok(scene)
            }

            /// The scene with the values of `params`, read by name and checked before any
            /// becomes a typed argument.
            fn from_table(params: &$crate::Params) -> Result<Self, ::lagrange::Error> {
                let [$($field),*] = params.values_of(PARAMS)?;
                $crate::params::check_all(PARAMS, &[$($field),*])?;
                Self::$constructor($($crate::params::ParamValue::from_f64($field)),*)
            }
        }
    };
}

/// The parameter items of a [`SceneType`](crate::SceneType) whose parameters are declared by
/// [`scene_params!`].
macro_rules! param_table {
    () => {
        const PARAMS: &'static [$crate::ParamSpec] = PARAMS;

        fn from_params(params: &$crate::Params) -> Result<Self, ::lagrange::Error> {
            Self::from_table(params)
        }
    };
}

pub(crate) use {param_table, scene_params};

/// A scene's parameter values, each checked against its specification.
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    /// The specifications, in the scene's order.
    specs: &'static [ParamSpec],
    /// One value per specification, in the same order.
    values: Vec<f64>,
}

impl Params {
    /// Every parameter at its default.
    pub fn defaults(specs: &'static [ParamSpec]) -> Params {
        Params { specs, values: specs.iter().map(|s| s.default).collect() }
    }

    /// Set a parameter by its name (`cart_mass`), its symbol (`M`) or the symbol spelled in ASCII
    /// (`alpha` for `α`, `omega` for `ω`: [`ParamSpec::ascii_symbol`]); all are case-sensitive (`M` and
    /// `m` are different masses).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an unknown key (listing the accepted names) or a value
    /// outside the parameter's domain (non-finite values are always rejected); the value is
    /// then left unchanged.
    pub fn set(&mut self, key: &str, value: f64) -> Result<(), Error> {
        let Some(index) = self.index_of_key(key) else {
            let accepted: Vec<String> = self
                .specs
                .iter()
                .map(|s| match s.ascii_symbol() {
                    ascii if ascii != s.symbol => format!("{} ({} or {ascii})", s.name, s.symbol),
                    _ => format!("{} ({})", s.name, s.symbol),
                })
                .collect();
            return Err(Error::InvalidParameter {
                name: key.to_string(),
                value,
                why: format!("unknown parameter; accepted: {}", accepted.join(", ")),
            });
        };
        self.specs[index].check(value)?;
        self.values[index] = value;
        Ok(())
    }

    /// The specification a key names, as [`set`](Self::set) resolves it (name, symbol, or the
    /// symbol in ASCII); `None` for an unknown key.
    pub fn spec(&self, key: &str) -> Option<&'static ParamSpec> {
        self.index_of_key(key).map(|index| &self.specs[index])
    }

    /// The value of the parameter called `name`.
    ///
    /// # Panics
    /// If no parameter has that name: a programming error (the names are fixed per scene).
    /// Scenes read their parameters through a fallible lookup instead.
    pub fn get(&self, name: &str) -> f64 {
        match self.specs.iter().position(|s| s.name == name) {
            Some(index) => self.values[index],
            None => panic!("no parameter named `{name}`; the parameters are {:?}", self.names()),
        }
    }

    /// The specifications, in order.
    pub fn specs(&self) -> &'static [ParamSpec] {
        self.specs
    }

    /// Every specification with its current value, in order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static ParamSpec, f64)> {
        self.specs.iter().zip(self.values.iter().copied())
    }

    /// The values of `specs` (looked up by name), in the order of `specs`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first parameter missing from this set (a set
    /// built for another scene).
    pub(crate) fn values_of<const N: usize>(&self, specs: &'static [ParamSpec]) -> Result<[f64; N], Error> {
        debug_assert_eq!(specs.len(), N, "a scene reads all of its parameters");
        let mut values = [0.0; N];
        for (value, spec) in values.iter_mut().zip(specs) {
            *value = match self.specs.iter().position(|s| s.name == spec.name) {
                Some(index) => self.values[index],
                None => {
                    return Err(Error::InvalidParameter {
                        name: spec.name.to_string(),
                        value: f64::NAN,
                        why: format!(
                            "missing from the parameter set {:?} (was it built for another scene?)",
                            self.names()
                        ),
                    });
                }
            };
        }
        Ok(values)
    }

    /// Position of the parameter whose name, or else whose symbol, or else whose symbol in ASCII
    /// is `key`.
    fn index_of_key(&self, key: &str) -> Option<usize> {
        let by_name = self.specs.iter().position(|s| s.name == key);
        let by_symbol = || self.specs.iter().position(|s| s.symbol == key);
        by_name.or_else(by_symbol).or_else(|| self.specs.iter().position(|s| s.ascii_symbol() == key))
    }

    /// The parameter names, in order.
    fn names(&self) -> Vec<&'static str> {
        self.specs.iter().map(|s| s.name).collect()
    }

    /// Overwrite a value without checking it, so that tests can reach the typed constructors'
    /// own validation through [`Scene::build`](crate::Scene::build).
    #[cfg(test)]
    pub(crate) fn set_unchecked(&mut self, name: &str, value: f64) {
        let index = self.specs.iter().position(|s| s.name == name);
        self.values[index.unwrap_or_else(|| panic!("test names an unknown parameter `{name}`"))] = value;
    }
}

/// `symbol` spelled in ASCII, as [`ParamSpec::ascii_symbol`] describes.
fn ascii_symbol(symbol: &str) -> String {
    const GREEK: [&str; 24] = [
        "alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota", "kappa", "lambda", "mu", "nu",
        "xi", "omicron", "pi", "rho", "sigma", "tau", "upsilon", "phi", "chi", "psi", "omega",
    ];
    let mut ascii = String::new();
    for c in symbol.chars() {
        // The lower-case letters α..ω are U+03B1..U+03C9 (with the final sigma ς at U+03C2),
        // the capitals Α..Ω U+0391..U+03A9 (with no letter at U+03A2).
        let (index, capital) = match c {
            'ς' => (Some(17), false),
            'α'..='ω' => (Some(c as usize - 'α' as usize - usize::from(c > 'ς')), false),
            'Α'..='Ω' if c != '\u{3a2}' => (Some(c as usize - 'Α' as usize - usize::from(c > '\u{3a2}')), true),
            _ => (None, false),
        };
        match index {
            Some(i) if capital => {
                ascii.push_str(&GREEK[i][..1].to_ascii_uppercase());
                ascii.push_str(&GREEK[i][1..]);
            }
            Some(i) => ascii.push_str(GREEK[i]),
            None => ascii.push(c),
        }
    }
    ascii
}

/// Check every value against its specification, in order (a typed scene's constructor
/// arguments against its `PARAMS`).
///
/// # Errors
/// [`Error::InvalidParameter`] for the first value outside its domain, naming that parameter.
pub(crate) fn check_all(specs: &[ParamSpec], values: &[f64]) -> Result<(), Error> {
    debug_assert_eq!(specs.len(), values.len(), "one value per parameter");
    specs.iter().zip(values).try_for_each(|(spec, &value)| spec.check(value))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPECS: &[ParamSpec] = &[
        ParamSpec::new("cart_mass", "M", "kg", 2.0, Domain::Positive, "mass of the cart"),
        ParamSpec::new("bob_mass", "m", "kg", 1.0, Domain::Positive, "mass of the bob"),
        ParamSpec::new("angle", "α", "rad", 0.5, Domain::OpenInterval(0.0, 1.5), "incline angle"),
        ParamSpec::new("links", "N", "", 4.0, Domain::Integer { min: 1, max: 256 }, "number of links"),
        ParamSpec::new("charge", "e", "C", 1.0, Domain::Finite, "charge"),
        GRAVITY,
    ];

    /// The error's parameter name and its reason, or a failure message.
    fn rejection(result: Result<(), Error>) -> (String, String) {
        match result {
            Err(Error::InvalidParameter { name, why, .. }) => (name, why),
            other => panic!("expected InvalidParameter, got {other:?}"),
        }
    }

    #[test]
    fn defaults_follow_the_specs() {
        let params = Params::defaults(SPECS);
        let got: Vec<f64> = params.iter().map(|(_, v)| v).collect();
        assert_eq!(got, vec![2.0, 1.0, 0.5, 4.0, 1.0, 9.81]);
        assert_eq!(params.specs().len(), SPECS.len());
        assert_eq!(params.get("gravity"), 9.81);
    }

    #[test]
    fn set_by_name_and_by_symbol_is_case_sensitive() {
        let mut params = Params::defaults(SPECS);
        params.set("cart_mass", 5.0).unwrap();
        params.set("m", 0.25).unwrap();
        params.set("g", 0.0).unwrap();
        assert_eq!(params.get("cart_mass"), 5.0, "set by name");
        assert_eq!(params.get("bob_mass"), 0.25, "symbol `m` is the bob, not the cart `M`");
        assert_eq!(params.get("gravity"), 0.0, "set by symbol");
        params.set("M", 7.0).unwrap();
        assert_eq!((params.get("cart_mass"), params.get("bob_mass")), (7.0, 0.25));
    }

    #[test]
    fn greek_symbols_have_ascii_spellings() {
        let spelled: Vec<String> = ["α", "ω", "θ", "λ", "μ", "σ", "ς", "τ", "Ω", "Δ", "m_p", "l'", "ω0"]
            .iter()
            .map(|s| ascii_symbol(s))
            .collect();
        let expected = [
            "alpha", "omega", "theta", "lambda", "mu", "sigma", "sigma", "tau", "Omega", "Delta", "m_p", "l'", "omega0",
        ];
        assert_eq!(spelled, expected);
        let mut params = Params::defaults(SPECS);
        params.set("alpha", 0.25).unwrap();
        assert_eq!(params.get("angle"), 0.25, "set by the ASCII spelling of α");
        assert_eq!(params.spec("alpha").map(|s| s.name), Some("angle"));
        assert_eq!(params.spec("α").map(|s| s.name), Some("angle"));
        assert_eq!(params.spec("M").map(|s| s.name), Some("cart_mass"));
        assert_eq!(params.spec("Alpha"), None, "case-sensitive");
        let (_, why) = rejection(params.set("beta", 1.0));
        assert!(why.contains("angle (α or alpha)"), "{why}");
    }

    #[test]
    fn unknown_key_lists_the_accepted_names() {
        let mut params = Params::defaults(SPECS);
        let (name, why) = rejection(params.set("cart", 1.0));
        assert_eq!(name, "cart");
        for spec in SPECS {
            assert!(why.contains(spec.name) && why.contains(spec.symbol), "`{why}` should list {}", spec.name);
        }
        assert_eq!(params, Params::defaults(SPECS), "a rejected set changes nothing");
    }

    #[test]
    fn values_outside_the_domain_are_rejected_with_the_parameter_named() {
        let mut params = Params::defaults(SPECS);
        let cases: &[(&str, f64, &str)] = &[
            ("cart_mass", f64::NAN, "finite"),
            ("cart_mass", f64::INFINITY, "finite"),
            ("cart_mass", 0.0, "positive"),
            ("bob_mass", -1.0, "positive"),
            ("gravity", -9.81, "non-negative"),
            ("angle", 0.0, "strictly between"),
            ("angle", 1.5, "strictly between"),
            ("links", 0.0, "integer from 1 to 256"),
            ("links", 2.5, "integer from 1 to 256"),
            ("links", 257.0, "integer from 1 to 256"),
            ("charge", f64::NEG_INFINITY, "finite"),
        ];
        for &(key, value, expected) in cases {
            let (name, why) = rejection(params.set(key, value));
            assert_eq!(name, key, "the error names the parameter");
            assert!(why.contains(expected), "{key} = {value}: expected `{expected}` in `{why}`");
        }
        assert_eq!(params, Params::defaults(SPECS));
        // Symbols name the parameter by its name in the error.
        assert_eq!(rejection(params.set("M", -2.0)).0, "cart_mass");
    }

    #[test]
    fn boundary_values_inside_the_domain_are_accepted() {
        let mut params = Params::defaults(SPECS);
        for (key, value) in [("gravity", 0.0), ("links", 1.0), ("links", 256.0), ("charge", -3.0), ("angle", 1e-9)] {
            params.set(key, value).unwrap();
            assert_eq!(params.get(key), value);
        }
    }

    #[test]
    fn values_of_reads_by_name_and_reports_a_foreign_set() {
        const REORDERED: &[ParamSpec] = &[SPECS[5], SPECS[0]];
        let params = Params::defaults(SPECS);
        assert_eq!(params.values_of::<2>(REORDERED), Ok([9.81, 2.0]));
        const OTHER: &[ParamSpec] = &[ParamSpec::new("stiffness", "k", "N/m", 1.0, Domain::Positive, "spring")];
        let error = params.values_of::<1>(OTHER).unwrap_err();
        assert!(matches!(error, Error::InvalidParameter { ref name, .. } if name == "stiffness"), "{error}");
    }
}
