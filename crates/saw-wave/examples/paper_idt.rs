//! The paper's transducer (20 finger pairs, 100 µm fingers and gaps, 9 mm aperture, 128° Y-X
//! LiNbO3, 125 V₀₋ₚ at 9.61 MHz) through the `saw_wave::idt` model: prints the comparison table
//! with the paper's 20 nm and 70 W, writes `results/paper_idt.json` and the charts
//! `figures/amplitude_vs_voltage.svg` and `figures/admittance_vs_frequency.svg` under the output
//! folder (default `validation/idt`).
//!
//! ```sh
//! cargo run -p saw-wave --example paper_idt                 # writes validation/idt/
//! cargo run -p saw-wave --example paper_idt -- --out /tmp/idt
//! ```

use std::error::Error;
use std::path::{Path, PathBuf};

use charts::{Chart, Series, Style};
use saw_wave::idt::Caveat;
use saw_wave::{
    Cut, ElectrodeMetal, EulerAngles, Idt, IdtResponse, IdtSubstrate, Metallisation, materials,
};
use serde::Serialize;

/// The paper's drive: 125 V₀₋ₚ at 9.61 MHz; its measured 20 nm, 1.1 m/s and 70 W.
const PAPER_VOLTAGE_PEAK_V: f64 = 125.0;
const PAPER_FREQUENCY_HZ: f64 = 9.61e6;
const PAPER_AMPLITUDE_M: f64 = 20e-9;
const PAPER_SPEED_M_PER_S: f64 = 1.1;
const PAPER_INPUT_POWER_W: f64 = 70.0;

/// The paper's transducer (section 3 of the paper, Fig. 4); fingers perfectly conducting.
fn paper_idt() -> Idt {
    Idt {
        finger_pairs: 20,
        finger_width_m: 100e-6,
        gap_m: 100e-6,
        aperture_m: 9e-3,
        metallisation: None,
    }
}

/// One row of the table: a transducer, a substrate and a drive frequency at 125 V.
#[derive(Serialize)]
struct Case {
    label: String,
    idt: Idt,
    substrate: IdtSubstrate,
    response: IdtResponse,
    caveats: Vec<String>,
    /// Peak voltage that gives the paper's 20 nm at the same frequency (V).
    voltage_for_paper_amplitude_v: f64,
    /// Real input power at that voltage (W).
    input_power_at_paper_amplitude_w: f64,
}

impl Case {
    fn new(
        label: &str,
        idt: Idt,
        substrate: &IdtSubstrate,
        f: f64,
    ) -> Result<Self, Box<dyn Error>> {
        let response = idt.drive(substrate, PAPER_VOLTAGE_PEAK_V, f)?;
        let scale = PAPER_AMPLITUDE_M / response.amplitude_uz_m;
        Ok(Self {
            label: label.to_owned(),
            caveats: response
                .admittance
                .caveats
                .iter()
                .map(Caveat::to_string)
                .collect(),
            voltage_for_paper_amplitude_v: PAPER_VOLTAGE_PEAK_V * scale,
            input_power_at_paper_amplitude_w: response.input_power_w * scale * scale,
            idt,
            substrate: substrate.clone(),
            response,
        })
    }
}

#[derive(Serialize)]
struct Paper {
    drive_voltage_peak_v: f64,
    frequency_hz: f64,
    amplitude_uz_m: f64,
    surface_speed_x_m_per_s: f64,
    input_power_w: f64,
}

#[derive(Serialize)]
struct VoltagePoint {
    drive_voltage_peak_v: f64,
    amplitude_uz_at_paper_frequency_m: f64,
    amplitude_uz_at_synchronism_m: f64,
    amplitude_uz_period_matched_m: f64,
}

#[derive(Serialize)]
struct FrequencyPoint {
    frequency_hz: f64,
    radiation_conductance_s: f64,
    radiation_susceptance_s: f64,
    capacitive_susceptance_s: f64,
    amplitude_uz_at_paper_voltage_m: f64,
}

#[derive(Serialize)]
struct Results {
    command: &'static str,
    paper: Paper,
    cases: Vec<Case>,
    voltage_sweep: Vec<VoltagePoint>,
    frequency_sweep: Vec<FrequencyPoint>,
}

fn main() -> Result<(), Box<dyn Error>> {
    let out = output_folder()?;
    let cut = Cut::from_name("128yx-linbo3")?;
    let kovacs = IdtSubstrate::from_cut(&cut)?;
    let warner = IdtSubstrate::from_cut(&Cut::new(
        "128yx-linbo3 (Warner constants)",
        materials::lithium_niobate_warner_1967(),
        EulerAngles::new(0.0, 38.0, 0.0),
    ))?;
    let clamped = IdtSubstrate {
        effective_permittivity_f_per_m: kovacs.effective_permittivity_clamped_f_per_m,
        ..kovacs.clone()
    };
    let f0 = kovacs.phase_velocity_free_m_per_s / paper_idt().period_m();
    let matched = period_matched(PAPER_FREQUENCY_HZ, &kovacs);
    let aluminium = |thickness_m| Idt {
        metallisation: Some(Metallisation {
            metal: ElectrodeMetal::Aluminium,
            thickness_m,
        }),
        ..paper_idt()
    };
    let cases = vec![
        Case::new(
            "paper IDT (λ₀ = 400 µm) at 9.61 MHz",
            paper_idt(),
            &kovacs,
            PAPER_FREQUENCY_HZ,
        )?,
        Case::new("paper IDT at its f₀", paper_idt(), &kovacs, f0)?,
        Case::new(
            "period matched to 9.61 MHz",
            matched.clone(),
            &kovacs,
            PAPER_FREQUENCY_HZ,
        )?,
        Case::new(
            "matched, ε∞ from clamped ε^S",
            matched.clone(),
            &clamped,
            PAPER_FREQUENCY_HZ,
        )?,
        Case::new(
            "matched, Warner 1967 constants",
            period_matched(PAPER_FREQUENCY_HZ, &warner),
            &warner,
            PAPER_FREQUENCY_HZ,
        )?,
        Case::new(
            "matched, Al fingers 100 nm",
            Idt {
                metallisation: aluminium(100e-9).metallisation,
                ..matched.clone()
            },
            &kovacs,
            PAPER_FREQUENCY_HZ,
        )?,
        Case::new(
            "paper IDT at 9.61 MHz, Al fingers 100 nm",
            aluminium(100e-9),
            &kovacs,
            PAPER_FREQUENCY_HZ,
        )?,
    ];
    let results = Results {
        command: "cargo run -p saw-wave --example paper_idt",
        paper: Paper {
            drive_voltage_peak_v: PAPER_VOLTAGE_PEAK_V,
            frequency_hz: PAPER_FREQUENCY_HZ,
            amplitude_uz_m: PAPER_AMPLITUDE_M,
            surface_speed_x_m_per_s: PAPER_SPEED_M_PER_S,
            input_power_w: PAPER_INPUT_POWER_W,
        },
        voltage_sweep: voltage_sweep(&kovacs, &matched, f0)?,
        frequency_sweep: frequency_sweep(&kovacs)?,
        cases,
    };
    print_table(&results);
    let json_path = out.join("results").join("paper_idt.json");
    std::fs::create_dir_all(json_path.parent().unwrap_or(&out))?;
    std::fs::write(&json_path, serde_json::to_string_pretty(&results)? + "\n")?;
    println!("wrote {}", json_path.display());
    for path in write_charts(&results, &out.join("figures"))? {
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// `--out DIR`, or `validation/idt` of the workspace.
fn output_folder() -> Result<PathBuf, Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    match (args.next().as_deref(), args.next()) {
        (None, _) => Ok(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation/idt")),
        (Some("--out"), Some(dir)) => Ok(PathBuf::from(dir)),
        _ => Err("usage: paper_idt [--out DIR]".into()),
    }
}

/// The paper's transducer with its period chosen so that f₀ = `frequency_hz` (η = ½ kept).
fn period_matched(frequency_hz: f64, substrate: &IdtSubstrate) -> Idt {
    let quarter = substrate.phase_velocity_free_m_per_s / frequency_hz / 4.0;
    Idt {
        finger_width_m: quarter,
        gap_m: quarter,
        ..paper_idt()
    }
}

fn voltage_sweep(
    substrate: &IdtSubstrate,
    matched: &Idt,
    f0: f64,
) -> Result<Vec<VoltagePoint>, Box<dyn Error>> {
    (0..=20)
        .map(|i| {
            let v = 50.0 + 5.0 * f64::from(i);
            Ok(VoltagePoint {
                drive_voltage_peak_v: v,
                amplitude_uz_at_paper_frequency_m: paper_idt()
                    .drive(substrate, v, PAPER_FREQUENCY_HZ)?
                    .amplitude_uz_m,
                amplitude_uz_at_synchronism_m: paper_idt().drive(substrate, v, f0)?.amplitude_uz_m,
                amplitude_uz_period_matched_m: matched
                    .drive(substrate, v, PAPER_FREQUENCY_HZ)?
                    .amplitude_uz_m,
            })
        })
        .collect()
}

fn frequency_sweep(substrate: &IdtSubstrate) -> Result<Vec<FrequencyPoint>, Box<dyn Error>> {
    (0..=240)
        .map(|i| {
            let f = 8.8e6 + 10e3 * f64::from(i);
            let r = paper_idt().drive(substrate, PAPER_VOLTAGE_PEAK_V, f)?;
            Ok(FrequencyPoint {
                frequency_hz: f,
                radiation_conductance_s: r.admittance.radiation_conductance_s,
                radiation_susceptance_s: r.admittance.radiation_susceptance_s,
                capacitive_susceptance_s: r.admittance.capacitive_susceptance_s,
                amplitude_uz_at_paper_voltage_m: r.amplitude_uz_m,
            })
        })
        .collect()
}

fn print_table(results: &Results) {
    println!(
        "| case | f (MHz) | f₀ (MHz) | (f − f₀)/f₀ | C_T (pF) | G_a (mS) | B_a (mS) | ωC_T (mS) | P_in (W) | P per direction (W) | \\|u_z\\| (nm) | ω\\|u_x\\| (m/s) | V₀₋ₚ for 20 nm | P_in at 20 nm (W) | 50 Ω forward (W) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for c in &results.cases {
        let r = &c.response;
        let a = &r.admittance;
        println!(
            "| {} | {:.3} | {:.3} | {:+.2} % | {:.1} | {:.3} | {:+.3} | {:.3} | {:.1} | {:.1} | {:.1} | {:.2} | {:.0} V | {:.1} | {:.1} |",
            c.label,
            a.frequency_hz / 1e6,
            a.synchronous_frequency_hz / 1e6,
            100.0 * a.relative_detuning,
            a.capacitance_f * 1e12,
            a.radiation_conductance_s * 1e3,
            a.radiation_susceptance_s * 1e3,
            a.capacitive_susceptance_s * 1e3,
            r.input_power_w,
            r.acoustic_power_per_direction_w,
            r.amplitude_uz_m * 1e9,
            r.surface_speed_x_m_per_s,
            c.voltage_for_paper_amplitude_v,
            c.input_power_at_paper_amplitude_w,
            r.forward_power_unmatched_w,
        );
    }
    let p = &results.paper;
    println!(
        "| paper (measured) | {:.2} | | | | | | | {:.0} | | {:.0} | {:.1} | {:.0} V | | |",
        p.frequency_hz / 1e6,
        p.input_power_w,
        p.amplitude_uz_m * 1e9,
        p.surface_speed_x_m_per_s,
        p.drive_voltage_peak_v
    );
    let first = &results.cases[0];
    let s = &first.substrate;
    println!(
        "\nsubstrate {}: v_f {:.1} m/s, v_m {:.1} m/s, K² {:.4}, ε∞/ε₀ {:.2} (clamped {:.2}); N_p·K² {:.3}, radiation Q {:.3}, f₀,met {:.3} MHz",
        s.cut,
        s.phase_velocity_free_m_per_s,
        s.phase_velocity_metallized_m_per_s,
        s.coupling_k2,
        s.effective_permittivity_f_per_m / saw_wave::VACUUM_PERMITTIVITY_F_PER_M,
        s.effective_permittivity_clamped_f_per_m / saw_wave::VACUUM_PERMITTIVITY_F_PER_M,
        first.response.admittance.np_k2,
        first.response.admittance.radiation_q,
        first
            .response
            .admittance
            .synchronous_frequency_metallized_hz
            / 1e6,
    );
    for c in &results.cases {
        for caveat in &c.caveats {
            println!("{}: {caveat}", c.label);
        }
    }
}

fn write_charts(results: &Results, folder: &Path) -> Result<Vec<PathBuf>, Box<dyn Error>> {
    let nm = |points: Vec<(f64, f64)>| points.into_iter().map(|(x, y)| (x, y * 1e9)).collect();
    let vs = &results.voltage_sweep;
    let mut amplitude = Chart::new(
        "Wave amplitude against drive voltage (paper IDT, 128° Y-X LiNbO3)",
        "drive voltage V₀₋ₚ (V)",
        "|u_z| (nm)",
    );
    amplitude.series = vec![
        Series::new(
            "λ₀ = 400 µm at 9.61 MHz",
            nm(vs
                .iter()
                .map(|p| (p.drive_voltage_peak_v, p.amplitude_uz_at_paper_frequency_m))
                .collect()),
            Style::Line,
        ),
        Series::new(
            "λ₀ = 400 µm at its f₀",
            nm(vs
                .iter()
                .map(|p| (p.drive_voltage_peak_v, p.amplitude_uz_at_synchronism_m))
                .collect()),
            Style::Line,
        ),
        Series::new(
            "period matched to 9.61 MHz",
            nm(vs
                .iter()
                .map(|p| (p.drive_voltage_peak_v, p.amplitude_uz_period_matched_m))
                .collect()),
            Style::Dashed,
        ),
        Series::new(
            "paper: 20 nm at 125 V",
            vec![(PAPER_VOLTAGE_PEAK_V, PAPER_AMPLITUDE_M * 1e9)],
            Style::Markers,
        ),
    ];
    let fs = &results.frequency_sweep;
    let ms = |get: fn(&FrequencyPoint) -> f64| -> Vec<(f64, f64)> {
        fs.iter()
            .map(|p| (p.frequency_hz / 1e6, get(p) * 1e3))
            .collect()
    };
    let mut admittance = Chart::new(
        "Radiation admittance of the paper IDT (20 pairs, λ₀ = 400 µm, W = 9 mm)",
        "frequency (MHz)",
        "admittance (mS)",
    );
    admittance.series = vec![
        Series::new("G_a", ms(|p| p.radiation_conductance_s), Style::Line),
        Series::new("B_a", ms(|p| p.radiation_susceptance_s), Style::Dashed),
        Series::new("ωC_T", ms(|p| p.capacitive_susceptance_s), Style::Line),
    ];
    admittance.shaded_x = vec![(
        PAPER_FREQUENCY_HZ / 1e6 - 0.005,
        PAPER_FREQUENCY_HZ / 1e6 + 0.005,
    )];
    let mut written = charts::write_chart(&amplitude, &folder.join("amplitude_vs_voltage"))?;
    written.extend(charts::write_chart(
        &admittance,
        &folder.join("admittance_vs_frequency"),
    )?);
    Ok(written)
}
