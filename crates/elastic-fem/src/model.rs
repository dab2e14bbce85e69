//! The problem data: nodes, tetrahedra, materials. Validated once at construction.

use rayon::prelude::*;

use crate::element::{
    Constitutive, GeometryDefect, POOR_SHAPE_QUALITY, check_geometry, is_straight_sided,
};
use crate::error::{FemError, FemResult};
use crate::material::Material;
use crate::shape::{Tet4, Tet10};

/// Element connectivity of a tetrahedral mesh (0-based node indices).
#[derive(Debug, Clone, PartialEq)]
pub enum Connectivity {
    /// Linear tetrahedra.
    Tet4(Vec<[usize; 4]>),
    /// Quadratic tetrahedra in gmsh node order (see [`crate::shape`]).
    Tet10(Vec<[usize; 10]>),
}

impl Connectivity {
    /// Number of elements.
    pub fn len(&self) -> usize {
        match self {
            Connectivity::Tet4(e) => e.len(),
            Connectivity::Tet10(e) => e.len(),
        }
    }

    /// Whether there are no elements.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Nodes per element (4 or 10).
    pub fn nodes_per_element(&self) -> usize {
        match self {
            Connectivity::Tet4(_) => 4,
            Connectivity::Tet10(_) => 10,
        }
    }

    /// The node indices of element `e`.
    pub fn element_nodes(&self, e: usize) -> &[usize] {
        match self {
            Connectivity::Tet4(c) => &c[e],
            Connectivity::Tet10(c) => &c[e],
        }
    }
}

/// Element shape statistics gathered at model construction.
#[derive(Debug, Clone, PartialEq)]
pub struct QualityReport {
    /// Smallest shape quality (1 = regular tetrahedron; see [`crate::element::shape_quality`]).
    pub min_quality: f64,
    /// Element with the smallest quality.
    pub worst_element: usize,
    /// Elements with quality below [`POOR_SHAPE_QUALITY`] (slivers, needles), accepted but
    /// suspicious: stresses there are unreliable.
    pub poor_elements: Vec<usize>,
    /// Number of curved Tet10 elements (mid-edge nodes off the edge midpoints).
    pub curved_elements: usize,
}

/// Nodes, elements and materials of a linear elastic body (or several bodies).
#[derive(Debug, Clone)]
pub struct Model {
    nodes: Vec<[f64; 3]>,
    connectivity: Connectivity,
    materials: Vec<Material>,
    laws: Vec<Constitutive>,
    element_material: Vec<u32>,
    curved: Vec<bool>,
    quality: QualityReport,
}

impl Model {
    /// Builds and validates a model: finite coordinates, node indices in range and distinct,
    /// every element neither inverted nor degenerate. All elements get `material`.
    pub fn new(
        nodes: Vec<[f64; 3]>,
        connectivity: Connectivity,
        material: Material,
    ) -> FemResult<Self> {
        material.validate()?;
        check_nodes(&nodes, &connectivity)?;
        let (quality, curved) = element_quality(&nodes, &connectivity)?;
        let n_elements = connectivity.len();
        Ok(Self {
            nodes,
            connectivity,
            laws: vec![Constitutive::from(&material)],
            materials: vec![material],
            element_material: vec![0; n_elements],
            curved,
            quality,
        })
    }

    /// Tet4 model from borrowed slices.
    pub fn tet4(nodes: &[[f64; 3]], tets: &[[usize; 4]], material: Material) -> FemResult<Self> {
        Self::new(nodes.to_vec(), Connectivity::Tet4(tets.to_vec()), material)
    }

    /// Tet10 model (gmsh node order) from borrowed slices.
    pub fn tet10(nodes: &[[f64; 3]], tets: &[[usize; 10]], material: Material) -> FemResult<Self> {
        Self::new(nodes.to_vec(), Connectivity::Tet10(tets.to_vec()), material)
    }

    /// Gives every element the same material.
    pub fn set_material(&mut self, material: Material) -> FemResult<()> {
        material.validate()?;
        self.laws = vec![Constitutive::from(&material)];
        self.materials = vec![material];
        self.element_material.iter_mut().for_each(|m| *m = 0);
        Ok(())
    }

    /// Per-element materials: element `e` uses `materials[element_material[e]]`.
    pub fn set_element_materials(
        &mut self,
        materials: Vec<Material>,
        element_material: Vec<usize>,
    ) -> FemResult<()> {
        if element_material.len() != self.element_count() {
            return Err(FemError::DimensionMismatch {
                what: "per-element material indices",
                expected: self.element_count(),
                found: element_material.len(),
            });
        }
        for m in &materials {
            m.validate()?;
        }
        for (e, &m) in element_material.iter().enumerate() {
            if m >= materials.len() {
                return Err(FemError::MaterialIndexOutOfRange {
                    element: e,
                    material: m,
                    count: materials.len(),
                });
            }
        }
        self.laws = materials.iter().map(Constitutive::from).collect();
        self.materials = materials;
        self.element_material = element_material.into_iter().map(|m| m as u32).collect();
        Ok(())
    }

    /// Node coordinates (m).
    pub fn nodes(&self) -> &[[f64; 3]] {
        &self.nodes
    }

    /// Element connectivity.
    pub fn connectivity(&self) -> &Connectivity {
        &self.connectivity
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of elements.
    pub fn element_count(&self) -> usize {
        self.connectivity.len()
    }

    /// Number of displacement unknowns, 3 × nodes. DOF of node n, component c: `3 n + c`.
    pub fn dof_count(&self) -> usize {
        3 * self.nodes.len()
    }

    /// Material of element `e`.
    pub fn material_of(&self, e: usize) -> &Material {
        &self.materials[self.element_material[e] as usize]
    }

    /// Prepared constitutive law of element `e`.
    pub fn constitutive_of(&self, e: usize) -> &Constitutive {
        &self.laws[self.element_material[e] as usize]
    }

    /// Whether Tet10 element `e` is curved (always false for Tet4).
    pub fn is_curved(&self, e: usize) -> bool {
        self.curved[e]
    }

    /// Element shape statistics.
    pub fn quality(&self) -> &QualityReport {
        &self.quality
    }

    /// Coordinates of the nodes of element `e`.
    pub(crate) fn element_coords<const N: usize>(&self, nodes: &[usize; N]) -> [[f64; 3]; N] {
        nodes.map(|n| self.nodes[n])
    }

    /// Axis-aligned bounding box (min, max) of the nodes (m).
    pub fn bounding_box(&self) -> ([f64; 3], [f64; 3]) {
        crate::locality::bounding_box(&self.nodes)
    }
}

/// Finite coordinates; every element's nodes in range and distinct.
fn check_nodes(nodes: &[[f64; 3]], connectivity: &Connectivity) -> FemResult<()> {
    for (i, x) in nodes.iter().enumerate() {
        if x.iter().any(|v| !v.is_finite()) {
            return Err(FemError::NonFiniteCoordinate {
                node: i,
                coordinates: *x,
            });
        }
    }
    let n_nodes = nodes.len();
    for e in 0..connectivity.len() {
        let en = connectivity.element_nodes(e);
        for (local, &node) in en.iter().enumerate() {
            if node >= n_nodes {
                return Err(FemError::NodeIndexOutOfRange {
                    element: e,
                    local,
                    node,
                    node_count: n_nodes,
                });
            }
            if en[..local].contains(&node) {
                return Err(FemError::RepeatedNodeInElement { element: e, node });
            }
        }
    }
    Ok(())
}

/// Every element's shape quality (an inverted or degenerate element is an error naming it)
/// and whether it is curved (a Tet10 with a midside node off its edge's midpoint).
fn element_quality(
    nodes: &[[f64; 3]],
    connectivity: &Connectivity,
) -> FemResult<(QualityReport, Vec<bool>)> {
    let checks: Vec<(Result<f64, GeometryDefect>, bool)> = match connectivity {
        Connectivity::Tet4(c) => c
            .par_iter()
            .map(|el| {
                let x = el.map(|n| nodes[n]);
                (check_geometry::<4, Tet4>(&x, false), false)
            })
            .collect(),
        Connectivity::Tet10(c) => c
            .par_iter()
            .map(|el| {
                let x = el.map(|n| nodes[n]);
                let curved = !is_straight_sided(&x);
                (check_geometry::<10, Tet10>(&x, curved), curved)
            })
            .collect(),
    };
    let mut quality = QualityReport {
        min_quality: f64::INFINITY,
        worst_element: 0,
        poor_elements: Vec::new(),
        curved_elements: 0,
    };
    let mut curved = Vec::with_capacity(checks.len());
    for (e, (check, is_curved)) in checks.into_iter().enumerate() {
        let q = match check {
            Ok(q) => q,
            Err(GeometryDefect::Inverted {
                det_jacobian,
                reference_point,
            }) => {
                return Err(FemError::InvertedElement {
                    element: e,
                    det_jacobian,
                    reference_point,
                });
            }
            Err(GeometryDefect::Degenerate { quality }) => {
                return Err(FemError::DegenerateElement {
                    element: e,
                    quality,
                    minimum: crate::element::MIN_SHAPE_QUALITY,
                });
            }
        };
        if q < quality.min_quality {
            quality.min_quality = q;
            quality.worst_element = e;
        }
        if q < POOR_SHAPE_QUALITY {
            quality.poor_elements.push(e);
        }
        quality.curved_elements += usize::from(is_curved);
        curved.push(is_curved);
    }
    Ok((quality, curved))
}
