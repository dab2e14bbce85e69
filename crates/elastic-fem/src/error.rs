//! The one error type of the crate.

use thiserror::Error;

/// Everything that can go wrong in `elastic-fem`. Each variant names the parameter, element,
/// node, degree of freedom or matrix column at fault.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FemError {
    /// A material constant is out of its admissible range or not finite.
    #[error("elastic-fem material: parameter `{parameter}` = {value} is invalid: {reason}")]
    InvalidMaterialParameter {
        /// Name of the parameter (e.g. `poisson_ratio`, `young_modulus_pa`, `c44_pa`).
        parameter: &'static str,
        /// The offending value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// A node coordinate is NaN or infinite.
    #[error("elastic-fem mesh: node {node} has a non-finite coordinate {coordinates:?}")]
    NonFiniteCoordinate {
        /// Node index (0-based).
        node: usize,
        /// Its coordinates.
        coordinates: [f64; 3],
    },
    /// An element refers to a node that does not exist.
    #[error(
        "elastic-fem mesh: element {element} local node {local} refers to node {node}, but the mesh has {node_count} nodes"
    )]
    NodeIndexOutOfRange {
        /// Element index (0-based).
        element: usize,
        /// Local node position inside the element.
        local: usize,
        /// The referenced node index.
        node: usize,
        /// Number of nodes in the mesh.
        node_count: usize,
    },
    /// An element lists the same node twice.
    #[error("elastic-fem mesh: element {element} lists node {node} more than once")]
    RepeatedNodeInElement {
        /// Element index (0-based).
        element: usize,
        /// The repeated node.
        node: usize,
    },
    /// The element Jacobian determinant is negative somewhere: the element is inverted
    /// (wrong node order or a tangled curved element).
    #[error(
        "elastic-fem mesh: element {element} is inverted (det J = {det_jacobian:e} < 0 at reference point {reference_point:?})"
    )]
    InvertedElement {
        /// Element index (0-based).
        element: usize,
        /// Jacobian determinant found (m³ per unit reference volume).
        det_jacobian: f64,
        /// Reference coordinates where it was found.
        reference_point: [f64; 3],
    },
    /// The element is (nearly) flat: its shape quality is below the admissible minimum.
    #[error(
        "elastic-fem mesh: element {element} is degenerate (shape quality {quality:e} < minimum {minimum:e}; 1 = regular tetrahedron)"
    )]
    DegenerateElement {
        /// Element index (0-based).
        element: usize,
        /// Its quality measure (see [`crate::element::shape_quality`]).
        quality: f64,
        /// The threshold it failed.
        minimum: f64,
    },
    /// A material table or per-element material index is inconsistent.
    #[error(
        "elastic-fem model: element {element} uses material {material}, but only {count} materials are defined"
    )]
    MaterialIndexOutOfRange {
        /// Element index.
        element: usize,
        /// Material index used.
        material: usize,
        /// Number of materials defined.
        count: usize,
    },
    /// Two sizes that must agree do not.
    #[error("elastic-fem: {what}: expected length {expected}, found {found}")]
    DimensionMismatch {
        /// What was being checked.
        what: &'static str,
        /// Expected size.
        expected: usize,
        /// Size found.
        found: usize,
    },
    /// A constraint or load refers to a node that does not exist.
    #[error("elastic-fem {context}: node {node} does not exist (mesh has {node_count} nodes)")]
    ConstraintNodeOutOfRange {
        /// Which constraint or load (e.g. `dirichlet[2]`, `rigid_face[0]`, `surface triangle 17`).
        context: String,
        /// The node index.
        node: usize,
        /// Number of nodes in the mesh.
        node_count: usize,
    },
    /// A periodic slave node found no master node at `position - translation`.
    #[error(
        "elastic-fem periodic pairs: slave node {slave_node} at {position:?} has no master node within {tolerance_m:e} m of {position:?} - {translation_m:?}"
    )]
    UnmatchedPeriodicNode {
        /// Slave node index.
        slave_node: usize,
        /// Slave node position (m).
        position: [f64; 3],
        /// Translation master → slave (m).
        translation_m: [f64; 3],
        /// Matching tolerance (m).
        tolerance_m: f64,
    },
    /// A periodic slave node matches more than one master node.
    #[error(
        "elastic-fem periodic pairs: slave node {slave_node} matches master nodes {first_master} and {second_master} within the tolerance {tolerance_m:e} m"
    )]
    AmbiguousPeriodicMatch {
        /// Slave node index.
        slave_node: usize,
        /// First candidate master.
        first_master: usize,
        /// Second candidate master.
        second_master: usize,
        /// Matching tolerance (m).
        tolerance_m: f64,
    },
    /// Constraints tie a degree of freedom to two different prescribed values.
    #[error(
        "elastic-fem constraints: node {node} component {component} is prescribed to both {first_m:e} m and {second_m:e} m (through Dirichlet, rigid-face or periodic ties)"
    )]
    ConflictingPrescribedValues {
        /// Node index.
        node: usize,
        /// Displacement component (0 = x, 1 = y, 2 = z).
        component: usize,
        /// First value (m).
        first_m: f64,
        /// Second value (m).
        second_m: f64,
    },
    /// A prescribed value, load or matrix entry is NaN or infinite.
    #[error("elastic-fem: {what} is not finite at node {node} component {component}")]
    NonFiniteInput {
        /// What was being checked (e.g. `load vector`, `Dirichlet value`).
        what: &'static str,
        /// Node index.
        node: usize,
        /// Component (0 = x, 1 = y, 2 = z).
        component: usize,
    },
    /// The constraints leave rigid-body motions free: the stiffness matrix is singular.
    #[error(
        "elastic-fem: rigid-body mode not constrained: {modes} (add Dirichlet conditions or ties that fix them)"
    )]
    UnconstrainedRigidBodyModes {
        /// Human-readable list, e.g. `body 0: translation z, rotation about x`.
        modes: String,
    },
    /// The Cholesky factorisation met a non-positive or negligibly small pivot.
    #[error(
        "elastic-fem sparse Cholesky: matrix not positive definite at column {column} (pivot / diagonal = {pivot_ratio:e}, minimum {minimum:e}); the system is singular or indefinite{location}"
    )]
    NotPositiveDefinite {
        /// Column (in the matrix's own numbering) where the factorisation failed.
        column: usize,
        /// Pivot divided by the original diagonal entry (0 or negative for a failed pivot).
        pivot_ratio: f64,
        /// Smallest accepted ratio.
        minimum: f64,
        /// Optional description of the node/component behind `column`.
        location: String,
    },
    /// A matrix handed to a numeric factorisation does not have the analysed sparsity pattern.
    #[error(
        "elastic-fem sparse Cholesky: the matrix pattern differs from the analysed one ({detail})"
    )]
    PatternMismatch {
        /// Which part differs.
        detail: String,
    },
    /// The solution contains NaN or infinite values.
    #[error("elastic-fem: solution is not finite at unknown {unknown}")]
    NonFiniteSolution {
        /// Index of the first non-finite unknown.
        unknown: usize,
    },
    /// The iterative solver did not reach its energy-error tolerance.
    #[error(
        "elastic-fem iterative solver (PCG): not converged after {iterations} iterations: {rule} (estimated relative energy error {relative_energy_error:e}, tolerance {tolerance:e})"
    )]
    IterativeNotConverged {
        /// Iterations performed.
        iterations: usize,
        /// Estimated relative energy-norm error reached (infinite before the first estimate).
        relative_energy_error: f64,
        /// The tolerance asked for.
        tolerance: f64,
        /// Which rule ended the iteration (iteration limit, breakdown).
        rule: String,
    },
    /// The reduced matrix has a (near-)null space of rigid-body motions: the system is singular
    /// or semi-definite, and both solver paths refuse it (CG would return one of infinitely
    /// many solutions of a consistent singular system without noticing; the Cholesky pivot check
    /// can miss it on a graded mesh).
    #[error(
        "elastic-fem: the system is singular: a rigid-body motion of the reduced unknowns has energy ratio qᵀKq / qᵀDq = {ratio:e} (≤ {tolerance:e}; D = diagonal of K); add Dirichlet conditions or ties that fix it"
    )]
    SingularSystem {
        /// Smallest generalised Rayleigh quotient qᵀ K q / qᵀ D q over the rigid-body motions q.
        ratio: f64,
        /// Largest ratio counted as singular.
        tolerance: f64,
    },
    /// The iterative path cannot handle this model (it is refused, not silently replaced).
    #[error("elastic-fem iterative solver: {reason}")]
    IterativeUnsupported {
        /// Why (e.g. Tet4 mesh without a p-multigrid hierarchy).
        reason: String,
    },
    /// A solver option is out of range.
    #[error("elastic-fem solver options: `{field}` = {value} is invalid: {reason}")]
    InvalidSolverOption {
        /// Field name.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// A failure reported by the sparse backend (out of memory, index overflow).
    #[error("elastic-fem sparse backend: {0}")]
    SparseBackend(String),
}

/// Shorthand for results of this crate.
pub type FemResult<T> = Result<T, FemError>;
