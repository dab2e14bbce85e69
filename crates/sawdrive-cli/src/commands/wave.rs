//! `sawdrive wave`: the Rayleigh wave of the stator's crystal cut and the power it carries;
//! with `wave.drive_voltage`, the `[stator.idt]` transducer's figures (f₀, detuning, admittance,
//! current, electrical input and acoustic powers, the amplitude it launches).

use anyhow::Context;
use sawdrive::scene::{Drive, Scene, load_scene};
use sawdrive::units::{Dimension, format_quantity};
use serde::Serialize;
use stick_slip::Warning;

use crate::cli::WaveArgs;

/// `sawdrive wave --json`: SI, unit in each key.
#[derive(Debug, Serialize)]
struct WaveReport<'a> {
    /// The scene's name.
    scene: String,
    /// The cut (`stator.cut`, or `--cut`).
    cut: String,
    /// The crystal's constant set, with its source.
    constant_set: String,
    /// ZXZ Euler angles (φ, θ, ψ) of the wave frame (degrees).
    euler_deg: [f64; 3],
    phase_velocity_free_m_per_s: f64,
    phase_velocity_metallized_m_per_s: f64,
    coupling_k2: f64,
    /// |u_x/u_z| at the free surface.
    displacement_ratio_ux_over_uz: f64,
    /// arg(u_x/u_z) at the free surface (degrees; +90°: retrograde).
    displacement_phase_ux_over_uz_deg: f64,
    /// The scene's frequency and normal amplitude, at which the power is given.
    frequency_hz: f64,
    normal_amplitude_m: f64,
    /// Power carried per unit beam width (free surface).
    power_per_width_w_per_m: f64,
    /// The beam width (`wave.aperture`).
    aperture_m: f64,
    /// The post array's width across y (`posts.array_y`).
    array_width_m: f64,
    /// Power flowing under the post array: per width × min(array width, aperture).
    power_under_array_w: f64,
    /// Power in the whole beam: per width × aperture.
    power_in_beam_w: f64,
    /// The phase velocity and tangential amplitude the scene's motor runs with, and where each
    /// came from (`cut`: "auto"; `given`).
    scene_phase_velocity_m_per_s: f64,
    phase_velocity_source: String,
    scene_tangential_amplitude_m: f64,
    tangential_amplitude_source: String,
    /// The scene's warnings (a given value more than 2 % off the cut's, a narrow beam, the
    /// transducer model's caveats, …).
    warnings: Vec<Warning>,
    /// With `wave.drive_voltage`: the resolved scene's drive section.
    #[serde(skip_serializing_if = "Option::is_none")]
    drive: Option<&'a Drive>,
    /// With `wave.drive_voltage`: the transducer model's whole response (admittance, powers,
    /// amplitudes, caveats), `saw_wave::IdtResponse`.
    #[serde(skip_serializing_if = "Option::is_none")]
    transducer: Option<&'a saw_wave::IdtResponse>,
}

pub fn run(args: &WaveArgs) -> anyhow::Result<()> {
    let scene = scene_of(args)?;
    let report = wave_report(&scene);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    for w in &report.warnings {
        eprintln!("warning: {}: {}", w.parameter, w.message);
    }
    print_table(&report);
    Ok(())
}

/// The scene of the command line, `--cut` applied as `stator.cut`.
fn scene_of(args: &WaveArgs) -> anyhow::Result<Scene> {
    let mut overrides = args.input.overrides.clone();
    if let Some(cut) = &args.cut {
        // Quoted as a TOML string, so that the name reaches stator.cut as written.
        overrides.push(format!("stator.cut={}", toml::Value::String(cut.clone())));
    }
    let scene = load_scene(args.input.scene.as_deref(), &overrides).with_context(|| {
        args.cut
            .as_ref()
            .map_or_else(String::new, |cut| format!("--cut {cut}"))
    })?;
    Ok(scene)
}

/// The wave of `scene`: the crystal's Rayleigh wave, the power it carries, what the scene uses.
fn wave_report(scene: &Scene) -> WaveReport<'_> {
    let motor = &scene.motor;
    let (wave, crystal) = (&motor.wave, &scene.crystal_wave);
    let per_width = crystal.power_per_width_w_per_m(wave.normal_amplitude_m, wave.frequency_hz);
    let array_width_m = motor.posts.array_y_m;
    WaveReport {
        scene: scene.name.clone(),
        cut: motor.stator_cut.name.clone(),
        constant_set: motor.stator_cut.crystal.clone(),
        euler_deg: motor.stator_cut.euler_deg,
        phase_velocity_free_m_per_s: crystal.phase_velocity_free_m_per_s,
        phase_velocity_metallized_m_per_s: crystal.phase_velocity_metallized_m_per_s,
        coupling_k2: crystal.coupling_k2,
        displacement_ratio_ux_over_uz: crystal.displacement_ratio_ux_over_uz,
        displacement_phase_ux_over_uz_deg: crystal.displacement_phase_ux_over_uz_deg,
        frequency_hz: wave.frequency_hz,
        normal_amplitude_m: wave.normal_amplitude_m,
        power_per_width_w_per_m: per_width,
        aperture_m: wave.aperture_m,
        array_width_m,
        power_under_array_w: per_width * array_width_m.min(wave.aperture_m),
        power_in_beam_w: per_width * wave.aperture_m,
        scene_phase_velocity_m_per_s: wave.phase_velocity_m_per_s,
        phase_velocity_source: scene.phase_velocity_source.clone(),
        scene_tangential_amplitude_m: wave.tangential_amplitude_m,
        tangential_amplitude_source: scene.tangential_amplitude_source.clone(),
        warnings: scene.warnings.clone(),
        drive: scene.drive.as_ref(),
        transducer: scene.drive.as_ref().map(|d| &d.response),
    }
}

/// The table `sawdrive wave` prints.
fn print_table(report: &WaveReport) {
    let e = report.euler_deg;
    println!(
        "Rayleigh wave of {} ({}, Euler {}°, {}°, {}°)\n",
        report.cut, report.constant_set, e[0], e[1], e[2]
    );
    let velocity = |v| format_quantity(v, Dimension::Velocity);
    let length = |v| format_quantity(v, Dimension::Length);
    let rows = [
        (
            "phase velocity, free surface",
            velocity(report.phase_velocity_free_m_per_s),
        ),
        (
            "phase velocity, metallized",
            velocity(report.phase_velocity_metallized_m_per_s),
        ),
        (
            "coupling K²",
            format!("{:.3} %", 100.0 * report.coupling_k2),
        ),
        (
            "|u_x/u_z| at the surface",
            format!(
                "{:.4} (phase {:.2}°)",
                report.displacement_ratio_ux_over_uz, report.displacement_phase_ux_over_uz_deg
            ),
        ),
        (
            "power per beam width",
            format!(
                "{:.4e} W/m at {} and {}",
                report.power_per_width_w_per_m,
                length(report.normal_amplitude_m),
                format_quantity(report.frequency_hz, Dimension::Frequency)
            ),
        ),
        (
            "power under the post array",
            format!(
                "{:.4} W ({} of {} array width in the beam)",
                report.power_under_array_w,
                length(report.array_width_m.min(report.aperture_m)),
                length(report.array_width_m)
            ),
        ),
        (
            "power in the beam",
            format!(
                "{:.4} W ({} aperture)",
                report.power_in_beam_w,
                length(report.aperture_m)
            ),
        ),
        (
            "scene's phase velocity",
            format!(
                "{} ({})",
                velocity(report.scene_phase_velocity_m_per_s),
                report.phase_velocity_source
            ),
        ),
        (
            "scene's tangential amplitude",
            format!(
                "{} ({})",
                length(report.scene_tangential_amplitude_m),
                report.tangential_amplitude_source
            ),
        ),
    ];
    for (name, value) in rows {
        println!("{name:<30} {value}");
    }
    if let Some(drive) = report.drive {
        print_drive(drive);
    }
}

/// The transducer's rows of the table.
fn print_drive(d: &Drive) {
    let t = &d.transducer;
    let length = |v| format_quantity(v, Dimension::Length);
    let frequency = |v| format_quantity(v, Dimension::Frequency);
    println!(
        "\ntransducer: {} finger pairs, {} fingers, {} gaps, {} aperture",
        t.finger_pairs,
        length(t.finger_width_m),
        length(t.gap_m),
        length(t.aperture_m)
    );
    let rows = [
        (
            "drive voltage",
            format!("{} V (peak)", d.drive_voltage_peak_v),
        ),
        (
            "synchronous frequency f₀",
            format!(
                "{} (drive {:+.2} % off it)",
                frequency(d.synchronous_frequency_hz),
                100.0 * d.relative_detuning
            ),
        ),
        ("N_p·K²", format!("{:.3}", d.np_k2)),
        ("capacitance C_T", format!("{:.4e} F", d.capacitance_f)),
        (
            "radiation conductance G_a",
            format!("{:.4e} S", d.radiation_conductance_s),
        ),
        ("current", format!("{:.4} A (peak)", d.current_peak_a)),
        (
            "electrical input power",
            format!("{:.4} W", d.electrical_input_power_w),
        ),
        (
            "acoustic power per direction",
            format!("{:.4} W", d.acoustic_power_per_direction_w),
        ),
        (
            "launched normal amplitude",
            format!(
                "{} ({} at f₀)",
                length(d.normal_amplitude_m),
                length(d.normal_amplitude_at_synchronism_m)
            ),
        ),
    ];
    for (name, value) in rows {
        println!("{name:<30} {value}");
    }
}
