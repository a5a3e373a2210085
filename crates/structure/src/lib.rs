//! Model descriptions of any linear structure.
//!
//! A structure model file (RON, the second kind of memid model file next to the slewing-rig
//! file) declares named parameters and writes the entries of the model's matrices as numbers or
//! as expressions of the parameters, for example `k1 + k2`, `-k2`, `alpha*m1 + beta*(k1 + k2)`,
//! `2*zeta*omega` or `sqrt(k/m)/(2*pi)`. [`StructureModel`] reads and validates the file once
//! (every error names `origin:line:column`), parses each expression once into an [`Expr`], and
//! then assembles the model for any num-dual scalar (`f64`, `Dual64`, `DualDVec64`, …), so
//! exact derivatives with respect to the parameters come out of the same code.
//!
//! # The models
//!
//! **Second order** (`SecondOrder`), in n coordinates q with m inputs u:
//!
//! ```text
//! M q̈ + D q̇ + K q = F u,      x = [q; q̇],
//! A = [[0, I], [−M⁻¹K, −M⁻¹D]],  B = [0; M⁻¹F],  x(0) = [q(0); q̇(0)]
//! ```
//!
//! formed by [`mem::SecondOrder`] (one LU of M, no inverse). D is given as a matrix, as
//! Rayleigh damping D = αM + βK, or by modal damping ratios ζ_i (lowest frequency first):
//! D = M Φ diag(2ζ_iω_i) Φᵀ M with Φ the mass-normalised modes of K φ = ω² M φ
//! (ΦᵀMΦ = I). The modes are computed over the scalar itself — Cholesky M = LLᵀ, then cyclic
//! Jacobi rotations on the symmetric S = L⁻¹KL⁻ᵀ (comparisons on real parts), Φ = L⁻ᵀV, so that
//! M Φ = L V — which makes the derivatives of D exact. An output row measures
//!
//! * `Displacement(q_i)`: C row e_i;  `Velocity(q_i)`: e_{n+i};
//! * `Acceleration(q_i)`: q̈_i = [M⁻¹(F u − D q̇ − K q)]_i, the row n+i of A in C and of B in D
//!   (the direct feedthrough of forces);
//! * `Combination([(quantity, w), …])`: Σ w × row, e.g. an inter-storey drift q2 − q1.
//!
//! **First order** (`FirstOrder`), in n states: ẋ = A x + B u, y = C x + D u with A and B
//! written entry by entry; an output measures `State(x_i)` (row e_i), an explicit `Row([…])`,
//! or a `Combination` of states, with an optional `feedthrough` row of D.
//!
//! **Effects** (`effects:`, module [`effects`]) add what a linear file leaves out: a sensor's
//! offset, scale, drift or quantization on an output, dry friction, drag or a cubic spring at a
//! coordinate (which make the model nonlinear: `models` integrates it), an unmodeled mode and an
//! appendage at a coordinate (two states each appended to the linear model). Their parameters
//! join the file's.
//!
//! Every entry — of M, K, D, F, A, B, the output weights and rows, the initial state — may be an
//! expression, so initial states too can be estimated. Derived names (`derived:`) are
//! expressions of the parameters and of the derived names above them, evaluated in order before
//! the entries.
//!
//! # The model file
//!
//! ```ron
//! (
//!     name: "Two-storey shear building",
//!     parameters: {                       // name: (value, unit?, free?, bounds?, typical?, description?)
//!         "m": (value: 1000, unit: "kg"),
//!         "k1": (value: 2.5e6, unit: "N/m", free: true, bounds: (0, 1e10), description: "storey 1"),
//!         "k2": (value: 2.0e6, unit: "N/m", free: true, bounds: (0, 1e10)),
//!         "zeta": (value: 0.02, free: true, bounds: (0, 1)),
//!     },
//!     derived: [("f1", "sqrt(k1/m)/(2*pi)")],            // optional, in order
//!     structure: SecondOrder(
//!         coordinates: ["q1", "q2"],
//!         mass: [["m", 0], [0, "m"]],
//!         stiffness: [["k1 + k2", "-k2"], ["-k2", "k2"]],
//!         damping: Modal(["zeta", "zeta"]),             // or Rayleigh(alpha: …, beta: …), Matrix([[…]])
//!         inputs: [(name: "u", unit: "N", force: [1, 0])], // optional: columns of F
//!     ),
//!     hold: Zero,                                        // optional: Zero (default) | FirstOrder
//!     outputs: [
//!         (column: "a2", measures: Acceleration("q2"), unit: "m/s^2"),
//!         (column: "drift", measures: Combination([(Displacement("q2"), 1), (Displacement("q1"), -1)])),
//!     ],
//!     initial: (displacement: [0, 0], velocity: [0, 0]), // optional, zeros when omitted
//! )
//! ```
//!
//! A first-order file writes `structure: FirstOrder(states: ["x1", "x2"], a: [[0, 1], ["-k", "-c"]],
//! b: [[0], [1]], inputs: [(name: "u", unit: "V")])`, outputs such as
//! `(column: "y", measures: Row([1, "g"]), feedthrough: ["d"])`, and `initial: (state: [1, 0])`.
//! Optional fields may be written bare or as `Some(…)`.
//!
//! # The expression language
//!
//! ```text
//! expr    := term (('+' | '-') term)*
//! term    := unary (('*' | '/') unary)*
//! unary   := ('-' | '+') unary | power
//! power   := primary ('^' unary)?          right-associative: 2^3^2 = 2^9, -x^2 = -(x^2), 2^-1 = 0.5
//! primary := number | name | name '(' expr ')' | '(' expr ')'
//! number  := 12 | 1.5 | .5 | 5. | 2.5e6 | 1E-3
//! name    := [A-Za-z_][A-Za-z0-9_]*
//! ```
//!
//! Whitespace may separate any two tokens. The functions are `sqrt`, `exp`, `ln` (alias `log`),
//! `sin`, `cos`, `tan` and `abs`; the only constant is `pi` (`e` is an ordinary name). Any other
//! name must be one of the parameters the expression is parsed with; the function names and
//! `pi` cannot be parameter names. Powers are written `^` (`**` is rejected).
//!
//! ```
//! use structure::Expr;
//!
//! let e = Expr::parse("alpha*m1 + beta*(k1 + k2)", &["alpha", "beta", "m1", "k1", "k2"])?;
//! assert_eq!(e.eval(&[0.1, 0.01, 2.0, 100.0, 50.0]), 0.1 * 2.0 + 0.01 * 150.0);
//! # Ok::<(), structure::ExprError>(())
//! ```

mod assemble;
mod compile;
pub mod effects;
mod error;
pub mod expr;
mod modal;
mod model;
mod modes;
mod scan;
mod schema;
mod write;

pub use effects::{Effect, EffectKind, StiffnessChange};
pub use error::StructureError;
pub use expr::{EvalError, Expr, ExprError};
pub use model::{ForceLaw, ForceParts, StructureModel, is_structure_file};
pub use modes::StructureMode;
