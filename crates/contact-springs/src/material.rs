//! Isotropic linear-elastic materials, with the slider's and stator's defaults.

use serde::{Deserialize, Serialize};

use crate::error::{SpringError, poisson, positive};

/// An isotropic linear-elastic material (SI units).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Short name used in reports (`si`, `linbo3`, or the user's).
    pub name: String,
    /// Shear modulus G (Pa).
    pub shear_modulus_pa: f64,
    /// Poisson's ratio ν, in (−1, 1/2).
    pub poisson_ratio: f64,
    /// Mass density ρ (kg/m³).
    pub density_kg_per_m3: f64,
}

impl Material {
    /// Silicon, isotropic Voigt–Reuss–Hill average of the cubic constants
    /// C11 = 165.7, C12 = 63.9, C44 = 79.6 GPa: G = 66.5 GPa, ν = 0.22, ρ = 2329 kg/m³
    /// (docs/physics.md §2; see [`Material::from_cubic_hill`]).
    pub fn silicon() -> Self {
        Self {
            name: "si".into(),
            shear_modulus_pa: 66.5e9,
            poisson_ratio: 0.22,
            density_kg_per_m3: 2329.0,
        }
    }

    /// 128° Y-rotated LiNbO3, isotropic average: G = 67.0 GPa, ν = 0.25, ρ = 4628 kg/m³
    /// (docs/physics.md §2). Do not derive the Rayleigh-wave speed from it.
    pub fn lithium_niobate() -> Self {
        Self {
            name: "linbo3".into(),
            shear_modulus_pa: 67.0e9,
            poisson_ratio: 0.25,
            density_kg_per_m3: 4628.0,
        }
    }

    /// A built-in material by name: `si` (silicon) or `linbo3` (lithium niobate), case-insensitive.
    pub fn named(name: &str) -> Option<Self> {
        match name.to_ascii_lowercase().as_str() {
            "si" | "silicon" => Some(Self::silicon()),
            "linbo3" | "lithium_niobate" | "lithium-niobate" => Some(Self::lithium_niobate()),
            _ => None,
        }
    }

    /// A material from shear modulus G, Poisson's ratio ν and density ρ, validated.
    pub fn from_shear(
        name: &str,
        shear_modulus_pa: f64,
        poisson_ratio: f64,
        density_kg_per_m3: f64,
    ) -> Result<Self, SpringError> {
        let material = Self {
            name: name.into(),
            shear_modulus_pa,
            poisson_ratio,
            density_kg_per_m3,
        };
        material.validate()?;
        Ok(material)
    }

    /// A material from Young's modulus E and ν: G = E / (2(1+ν)).
    pub fn from_young(
        name: &str,
        youngs_modulus_pa: f64,
        poisson_ratio: f64,
        density_kg_per_m3: f64,
    ) -> Result<Self, SpringError> {
        let e = positive("youngs_modulus_pa", youngs_modulus_pa)?;
        let nu = poisson(poisson_ratio)?;
        Self::from_shear(name, e / (2.0 * (1.0 + nu)), nu, density_kg_per_m3)
    }

    /// Isotropic Voigt–Reuss–Hill average of a cubic crystal (Hill 1952):
    /// K = (C11 + 2C12)/3; G_V = (C11 − C12 + 3C44)/5; G_R = 5(C11 − C12)C44 / (4C44 + 3(C11 − C12));
    /// G = (G_V + G_R)/2; ν = (3K − 2G) / (2(3K + G)).
    pub fn from_cubic_hill(
        name: &str,
        c11_pa: f64,
        c12_pa: f64,
        c44_pa: f64,
        density_kg_per_m3: f64,
    ) -> Result<Self, SpringError> {
        let c44 = positive("c44_pa", c44_pa)?;
        let shear = positive("c11_pa - c12_pa", c11_pa - c12_pa)?;
        let bulk = positive("(c11_pa + 2 c12_pa) / 3", (c11_pa + 2.0 * c12_pa) / 3.0)?;
        let voigt = (shear + 3.0 * c44) / 5.0;
        let reuss = 5.0 * shear * c44 / (4.0 * c44 + 3.0 * shear);
        let g = 0.5 * (voigt + reuss);
        let nu = (3.0 * bulk - 2.0 * g) / (2.0 * (3.0 * bulk + g));
        Self::from_shear(name, g, nu, density_kg_per_m3)
    }

    /// Check every parameter: G > 0, ν ∈ (−1, 1/2), ρ > 0, all finite.
    pub fn validate(&self) -> Result<(), SpringError> {
        positive("shear_modulus_pa", self.shear_modulus_pa)?;
        poisson(self.poisson_ratio)?;
        positive("density_kg_per_m3", self.density_kg_per_m3)?;
        Ok(())
    }

    /// Young's modulus E = 2G(1+ν) (Pa).
    pub fn youngs_modulus_pa(&self) -> f64 {
        2.0 * self.shear_modulus_pa * (1.0 + self.poisson_ratio)
    }

    /// Lamé's first parameter λ = 2Gν/(1−2ν) (Pa).
    pub fn lame_lambda_pa(&self) -> f64 {
        2.0 * self.shear_modulus_pa * self.poisson_ratio / (1.0 - 2.0 * self.poisson_ratio)
    }

    /// Bulk shear wave speed c_s = √(G/ρ) (m/s).
    pub fn shear_wave_speed_m_per_s(&self) -> f64 {
        (self.shear_modulus_pa / self.density_kg_per_m3).sqrt()
    }
}
