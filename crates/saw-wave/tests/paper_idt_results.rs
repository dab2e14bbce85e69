//! The committed `validation/idt/results/paper_idt.json` (written by
//! `cargo run -p saw-wave --example paper_idt`) against the library as it is now: the paper's
//! transducer at 9.61 MHz and at its own f₀, 125 V₀₋ₚ. A change of the model or the constants that
//! is not followed by a regeneration of the study fails here.

use saw_wave::{Cut, Idt, IdtSubstrate};

const RESULTS: &str = include_str!("../../../validation/idt/results/paper_idt.json");

fn number(value: &serde_json::Value, pointer: &str) -> f64 {
    value
        .pointer(pointer)
        .and_then(serde_json::Value::as_f64)
        .unwrap_or_else(|| panic!("paper_idt.json has no number at {pointer}"))
}

#[test]
fn committed_paper_idt_results_match_the_library() {
    let results: serde_json::Value = serde_json::from_str(RESULTS).expect("paper_idt.json parses");
    let substrate = IdtSubstrate::from_cut(&Cut::from_name("128yx-linbo3").unwrap()).unwrap();
    let idt = Idt {
        finger_pairs: 20,
        finger_width_m: 100e-6,
        gap_m: 100e-6,
        aperture_m: 9e-3,
        metallisation: None,
    };
    let f0 = substrate.phase_velocity_free_m_per_s / idt.period_m();
    for (case, frequency_hz) in [(0, 9.61e6), (1, f0)] {
        let r = idt.drive(&substrate, 125.0, frequency_hz).unwrap();
        for (field, fresh) in [
            ("amplitude_uz_m", r.amplitude_uz_m),
            ("input_power_w", r.input_power_w),
            (
                "acoustic_power_per_direction_w",
                r.acoustic_power_per_direction_w,
            ),
            (
                "admittance/radiation_conductance_s",
                r.admittance.radiation_conductance_s,
            ),
            ("admittance/capacitance_f", r.admittance.capacitance_f),
        ] {
            let committed = number(&results, &format!("/cases/{case}/response/{field}"));
            assert!(
                (committed / fresh - 1.0).abs() < 1e-9,
                "case {case} {field}: committed {committed}, library {fresh}; regenerate with \
                 `cargo run -p saw-wave --example paper_idt`"
            );
        }
    }
}
