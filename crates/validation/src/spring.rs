//! The four punch problems behind the Johnson springs (docs/physics.md §3): which boundary condition
//! each imposes on the punch disk r < a, which symmetry it has, and its analytic value.

use std::fmt;

use contact_springs::Material;
use serde::{Deserialize, Serialize};

use crate::error::ValidationError;
use crate::point_load::PointForce;

/// One of the four contact springs of a rigid circular post.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Spring {
    /// Bonded normal: punch nodes u = (0, 0, −δ). Johnson/Mossakovskii eq (1), exact.
    #[serde(rename = "k_pn")]
    BondedNormal,
    /// Bonded tangential: punch nodes u = (δ, 0, 0). Eq (2), an approximation (see README).
    #[serde(rename = "k_pt")]
    BondedTangential,
    /// Frictionless normal: u_z = −δ, u_x and u_y free. Eq (3) = 2E*a, exact (Boussinesq).
    #[serde(rename = "k_sn")]
    FrictionlessNormal,
    /// Tangential with the normal displacement free: u_x = δ, u_y = 0, u_z free. Eq (4), exact:
    /// the traction q_x ∝ (a² − r²)^(−1/2) on the disk gives a uniform u_x and u_y = 0 there
    /// (Johnson 1985, ch. 3, tangential traction on a circular region).
    #[serde(rename = "k_st")]
    FreeNormalTangential,
}

/// How one displacement component of the punch nodes is treated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PunchComponent {
    /// Prescribed to `factor × δ`.
    Prescribed(f64),
    /// Left free (traction-free in that component).
    Free,
}

impl Spring {
    /// All four, in report order.
    pub const ALL: [Spring; 4] = [
        Spring::BondedNormal,
        Spring::BondedTangential,
        Spring::FrictionlessNormal,
        Spring::FreeNormalTangential,
    ];

    /// The short name used in reports and JSON (`k_pn`, `k_pt`, `k_sn`, `k_st`).
    pub fn label(&self) -> &'static str {
        match self {
            Spring::BondedNormal => "k_pn",
            Spring::BondedTangential => "k_pt",
            Spring::FrictionlessNormal => "k_sn",
            Spring::FreeNormalTangential => "k_st",
        }
    }

    /// Parses `k_pn`, `k_pt`, `k_sn` or `k_st`.
    pub fn from_label(label: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.label() == label)
    }

    /// The boundary condition on the punch disk, in words.
    pub fn condition(&self) -> &'static str {
        match self {
            Spring::BondedNormal => "bonded normal: u = (0, 0, -d)",
            Spring::BondedTangential => "bonded tangential: u = (d, 0, 0)",
            Spring::FrictionlessNormal => "frictionless normal: u_z = -d, u_x, u_y free",
            Spring::FreeNormalTangential => "tangential, u_z free: u_x = d, u_y = 0",
        }
    }

    /// Whether the punch is pushed along the normal (otherwise along +x).
    pub fn is_normal(&self) -> bool {
        matches!(self, Spring::BondedNormal | Spring::FrictionlessNormal)
    }

    /// Whether the punch disk is bonded (all three components prescribed).
    pub fn is_bonded(&self) -> bool {
        matches!(self, Spring::BondedNormal | Spring::BondedTangential)
    }

    /// Punch-node condition per component x, y, z, as multiples of the punch displacement δ.
    pub fn punch_components(&self) -> [PunchComponent; 3] {
        use PunchComponent::{Free, Prescribed};
        match self {
            Spring::BondedNormal => [Prescribed(0.0), Prescribed(0.0), Prescribed(-1.0)],
            Spring::BondedTangential => [Prescribed(1.0), Prescribed(0.0), Prescribed(0.0)],
            Spring::FrictionlessNormal => [Free, Free, Prescribed(-1.0)],
            Spring::FreeNormalTangential => [Prescribed(1.0), Prescribed(0.0), Free],
        }
    }

    /// The resultant the punch exerts on the half-space, as a unit point force (its far field).
    pub fn point_force(&self) -> PointForce {
        if self.is_normal() {
            PointForce::NormalIntoSolid
        } else {
            PointForce::TangentialX
        }
    }

    /// The spring with the same load direction and the other interface condition (bonded ↔
    /// frictional): the "wrong boundary condition" partner used to show that the FEM tells the
    /// two apart.
    pub fn partner(&self) -> Spring {
        match self {
            Spring::BondedNormal => Spring::FrictionlessNormal,
            Spring::BondedTangential => Spring::FreeNormalTangential,
            Spring::FrictionlessNormal => Spring::BondedNormal,
            Spring::FreeNormalTangential => Spring::BondedTangential,
        }
    }

    /// The analytic stiffness (N/m) from `contact-springs` (docs/physics.md §3, eqs (1)–(4)).
    pub fn analytic_n_per_m(
        &self,
        material: &Material,
        radius_m: f64,
    ) -> Result<f64, ValidationError> {
        let k = match self {
            Spring::BondedNormal => contact_springs::k_pn(material, radius_m),
            Spring::BondedTangential => contact_springs::k_pt(material, radius_m),
            Spring::FrictionlessNormal => contact_springs::k_sn(material, radius_m),
            Spring::FreeNormalTangential => contact_springs::k_st(material, radius_m),
        };
        k.map_err(|source| ValidationError::Formula {
            spring: self.label(),
            source,
        })
    }
}

impl fmt::Display for Spring {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.label())
    }
}
