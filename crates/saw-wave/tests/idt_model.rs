//! The interdigital-transducer model (`saw_wave::idt`) against independent evaluations: the
//! closed-form admittance against the sum over electrode sources, Smith's sinc² as the many-pair
//! limit, the sinc zeros, Morgan's G_a0 = 8K²f₀C_sWN_p² from the crate's own K², the power books
//! (source = waves + fingers, each wave carrying its power by the crate's Poynting flux), the
//! finger resistance, and named errors for bad fields.

use std::f64::consts::PI;

use saw_wave::idt::{Caveat, radiation_admittance_ratio};
use saw_wave::{
    Cut, ElectrodeMetal, Idt, IdtSubstrate, Metallisation, VACUUM_PERMITTIVITY_F_PER_M, WaveError,
    materials,
};

const C64_ZERO: (f64, f64) = (0.0, 0.0);

fn paper_idt() -> Idt {
    Idt {
        finger_pairs: 20,
        finger_width_m: 100e-6,
        gap_m: 100e-6,
        aperture_m: 9e-3,
        metallisation: None,
    }
}

fn substrate(name: &str) -> IdtSubstrate {
    IdtSubstrate::from_cut(&Cut::from_name(name).unwrap()).unwrap()
}

/// Σₙ Σₘ (−1)ⁿ⁺ᵐ e^{−jk|x_n − x_m|}/M² over electrode centres x_n = n·p_e, summed term by term.
fn double_sum_over_sources(pairs: u32, wavenumber_times_pitch: f64) -> (f64, f64) {
    let m = 2 * pairs as usize;
    let (mut re, mut im) = C64_ZERO;
    for n in 0..m {
        for k in 0..m {
            let sign = if (n + k) % 2 == 0 { 1.0 } else { -1.0 };
            let phase = wavenumber_times_pitch * (n as f64 - k as f64).abs();
            re += sign * phase.cos();
            im -= sign * phase.sin();
        }
    }
    let norm = (m * m) as f64;
    (re / norm, im / norm)
}

/// |Σₙ (−1)ⁿ e^{−jk x_n}|²/M²: the array factor of the sources, squared.
fn single_sum_squared(pairs: u32, wavenumber_times_pitch: f64) -> f64 {
    let m = 2 * pairs as usize;
    let (mut re, mut im) = C64_ZERO;
    for n in 0..m {
        let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
        re += sign * (wavenumber_times_pitch * n as f64).cos();
        im -= sign * (wavenumber_times_pitch * n as f64).sin();
    }
    (re * re + im * im) / (m * m) as f64
}

#[test]
fn delta_model_closed_form_matches_the_sum_over_electrode_sources() {
    let detunings = [
        -0.9, -0.41, -0.1, -0.05, -0.013, -1e-4, -1e-9, 0.0, 3e-7, 2e-3, 0.025, 0.05, 0.3, 0.77,
    ];
    for pairs in [1, 2, 5, 20, 37] {
        let mut worst: f64 = 0.0;
        for &d in detunings
            .iter()
            .chain(&[1.0 / f64::from(pairs), -1.0 / f64::from(pairs)])
        {
            // k·p_e = (2πf/v)·(λ₀/2) = π f/f₀.
            let kp = PI * (1.0 + d);
            let (g, b) = radiation_admittance_ratio(pairs, d);
            let (g_sum, b_sum) = double_sum_over_sources(pairs, kp);
            let g_single = single_sum_squared(pairs, kp);
            worst = worst
                .max((g - g_sum).abs())
                .max((b - b_sum).abs())
                .max((g - g_single).abs());
        }
        assert!(
            worst < 1e-10,
            "Np = {pairs}: G_a/G_a0, B_a/G_a0 closed form vs the source sums differ by {worst:e}"
        );
    }
}

#[test]
fn smith_sinc_squared_is_the_many_pair_limit_with_second_order_error() {
    // X = N_p·δ across the main lobe and two side lobes.
    let error_at = |pairs: u32| {
        let mut worst: f64 = 0.0;
        for i in 1..=200 {
            let x = -2.5 * PI + 5.0 * PI * f64::from(i) / 201.0;
            let detuning = x / (PI * f64::from(pairs));
            let (g, b) = radiation_admittance_ratio(pairs, detuning);
            let sinc2 = (x.sin() / x).powi(2);
            let smith_b = ((2.0 * x).sin() - 2.0 * x) / (2.0 * x * x);
            worst = worst.max((g - sinc2).abs()).max((b - smith_b).abs());
        }
        worst
    };
    let (coarse, fine) = (error_at(20), error_at(200));
    assert!(
        coarse < 0.01,
        "G_a, B_a vs Smith's forms at Np = 20: {coarse}"
    );
    // δ = X/N_p: the difference falls as 1/N_p² (ratio 100 for 10× the pairs).
    let rate = coarse / fine;
    assert!(
        (70.0..130.0).contains(&rate),
        "error ratio Np = 20 vs 200 is {rate}, expected ≈ 100 (second order in 1/Np)"
    );
}

#[test]
fn conductance_zeros_lie_at_f0_times_one_plus_minus_one_over_np() {
    for pairs in 1..=50 {
        let np = f64::from(pairs);
        for sign in [-1.0, 1.0] {
            let (g, _) = radiation_admittance_ratio(pairs, sign / np);
            assert!(
                g < 1e-25,
                "Np = {pairs}: G_a/G_a0 at f₀(1 {sign:+}/Np) = {g:e}"
            );
            let (inside, _) = radiation_admittance_ratio(pairs, 0.5 * sign / np);
            assert!(
                inside > 0.3,
                "Np = {pairs}: main lobe at half width {inside}"
            );
        }
    }
}

#[test]
fn single_pair_conductance_is_cos_squared_and_susceptance_minus_half_sine() {
    for i in -20..=20 {
        let d = 0.049 * f64::from(i);
        let delta = PI * d;
        let (g, b) = radiation_admittance_ratio(1, d);
        assert!((g - (0.5 * delta).cos().powi(2)).abs() < 1e-14, "G at {d}");
        assert!((b + 0.5 * delta.sin()).abs() < 1e-14, "B at {d}: {b}");
    }
}

#[test]
fn synchronous_conductance_is_eight_k2_f0_cs_w_np2_from_the_crates_coupling() {
    let cut = Cut::from_name("128yx-linbo3").unwrap();
    let wave = cut.solve().unwrap();
    let sub = IdtSubstrate::new(&cut, &wave).unwrap();
    let idt = paper_idt();
    let f0 = wave.phase_velocity_free_m_per_s / 400e-6;
    let adm = idt.admittance(&sub, f0).unwrap();
    assert!((adm.synchronous_frequency_hz / f0 - 1.0).abs() < 1e-15);
    // η = ½: C_s = ε∞ (K(sin 45°)/K(cos 45°) = 1).
    let eps = sub.effective_permittivity_f_per_m;
    assert!((adm.capacitance_per_pair_per_length_f_per_m / eps - 1.0).abs() < 1e-14);
    assert!((adm.capacitance_f / (20.0 * eps * 9e-3) - 1.0).abs() < 1e-14);
    let expected = 8.0 * wave.coupling_k2 * f0 * eps * 9e-3 * 400.0;
    for (what, value) in [
        ("G_a0", adm.radiation_conductance_synchronous_s),
        ("G_a(f0)", adm.radiation_conductance_s),
    ] {
        assert!(
            (value / expected - 1.0).abs() < 1e-12,
            "{what} = {value} S vs 8K²f₀C_sWN_p² = {expected} S"
        );
    }
    assert!(adm.radiation_susceptance_s.abs() < 1e-12 * expected);
    let q = PI / (4.0 * 20.0 * wave.coupling_k2);
    assert!(
        (adm.radiation_q / q - 1.0).abs() < 1e-12,
        "radiation Q {} vs π/(4N_pK²) {q}",
        adm.radiation_q
    );
}

#[test]
fn capacitance_grows_with_the_metallisation_ratio_and_is_symmetric_about_one_half() {
    let sub = substrate("128yx-linbo3");
    let cs = |width: f64| {
        let idt = Idt {
            finger_width_m: width,
            gap_m: 200e-6 - width,
            ..paper_idt()
        };
        idt.admittance(&sub, 9.6e6)
            .unwrap()
            .capacitance_per_pair_per_length_f_per_m
            / sub.effective_permittivity_f_per_m
    };
    let ratios: Vec<f64> = [20e-6, 60e-6, 100e-6, 140e-6, 180e-6]
        .iter()
        .map(|&w| cs(w))
        .collect();
    assert!(
        ratios.windows(2).all(|r| r[1] > r[0]),
        "C_s/ε∞ must grow with η: {ratios:?}"
    );
    // K(sin)/K(cos) at η and 1 − η are reciprocal (swapping metal and gap).
    assert!((ratios[0] * ratios[4] - 1.0).abs() < 1e-13, "{ratios:?}");
    assert!((ratios[1] * ratios[3] - 1.0).abs() < 1e-13, "{ratios:?}");
}

#[test]
fn power_books_close_and_the_wave_carries_the_power_launched() {
    let cut = Cut::from_name("128yx-linbo3").unwrap();
    let wave = cut.solve().unwrap();
    let sub = IdtSubstrate::new(&cut, &wave).unwrap();
    let resistive = Idt {
        metallisation: Some(Metallisation {
            metal: ElectrodeMetal::Aluminium,
            thickness_m: 50e-9,
        }),
        ..paper_idt()
    };
    for idt in [paper_idt(), resistive] {
        for f in [9.2e6, 9.61e6, 9.99e6, 10.4e6] {
            let r = idt.drive(&sub, 125.0, f).unwrap();
            let books = r.acoustic_power_w + r.ohmic_power_w;
            assert!(
                (r.input_power_w / books - 1.0).abs() < 1e-12,
                "P_in {} W vs P_ac + P_Ω {books} W at {f} Hz",
                r.input_power_w
            );
            assert!(
                (2.0 * r.acoustic_power_per_direction_w / r.acoustic_power_w - 1.0).abs() < 1e-15
            );
            // Absorbed by G_a at the transducer voltage.
            let absorbed =
                0.5 * r.transducer_voltage_peak_v.powi(2) * r.admittance.radiation_conductance_s;
            assert!((absorbed / r.acoustic_power_w - 1.0).abs() < 1e-12);
            // The launched wave, through the crate's Poynting flux, carries P per direction.
            let carried =
                wave.power_per_width_w_per_m(r.amplitude_uz_m, f).unwrap() * idt.aperture_m;
            assert!(
                (carried / r.acoustic_power_per_direction_w - 1.0).abs() < 1e-12,
                "wave of {} m carries {carried} W, launched {} W",
                r.amplitude_uz_m,
                r.acoustic_power_per_direction_w
            );
            // A 50 Ω source delivers its forward power less the reflected part.
            let delivered =
                r.forward_power_unmatched_w * (1.0 - r.reflection_coefficient_abs.powi(2));
            assert!((delivered / r.input_power_w - 1.0).abs() < 1e-12);
            assert!(r.input_power_w <= r.forward_power_unmatched_w * (1.0 + 1e-12));
        }
    }
}

#[test]
fn amplitude_is_proportional_to_voltage_and_peaks_at_synchronism() {
    let sub = substrate("128yx-linbo3");
    let idt = paper_idt();
    let f0 = sub.phase_velocity_free_m_per_s / idt.period_m();
    let a = idt.drive(&sub, 50.0, 9.61e6).unwrap();
    let b = idt.drive(&sub, 150.0, 9.61e6).unwrap();
    assert!((b.amplitude_uz_m / a.amplitude_uz_m - 3.0).abs() < 1e-12);
    let at_f0 = idt.drive(&sub, 125.0, f0).unwrap();
    assert!((at_f0.amplitude_uz_m / at_f0.amplitude_uz_at_synchronism_m - 1.0).abs() < 1e-14);
    for f in [0.97 * f0, 0.99 * f0, 1.01 * f0, 1.03 * f0] {
        let r = idt.drive(&sub, 125.0, f).unwrap();
        assert!(r.amplitude_uz_m < at_f0.amplitude_uz_m, "{f} Hz");
        assert!((r.amplitude_uz_at_synchronism_m / at_f0.amplitude_uz_m - 1.0).abs() < 1e-14);
    }
}

#[test]
fn detuned_strongly_coupled_drive_says_so() {
    let sub = substrate("128yx-linbo3");
    let r = paper_idt().drive(&sub, 125.0, 9.61e6).unwrap();
    let caveats = &r.admittance.caveats;
    assert!(
        caveats
            .iter()
            .any(|c| matches!(c, Caveat::StrongCoupling { np_k2 } if (1.0..1.2).contains(np_k2))),
        "{caveats:?}"
    );
    let detuned = caveats.iter().find_map(|c| match c {
        Caveat::Detuned {
            relative_detuning, ..
        } => Some(*relative_detuning),
        _ => None,
    });
    let expected = 9.61e6 / r.admittance.synchronous_frequency_hz - 1.0;
    let detuned = detuned.unwrap_or_else(|| panic!("no Detuned caveat: {caveats:?}"));
    assert!(
        (detuned / expected - 1.0).abs() < 1e-12,
        "{detuned} vs {expected}"
    );
    assert!(
        (-0.04..-0.035).contains(&detuned),
        "9.61 MHz on λ₀ = 400 µm: {detuned}"
    );
    assert!(
        caveats
            .iter()
            .any(|c| c.to_string().contains("off the synchronous frequency"))
    );
    // Weakly coupled quartz at synchronism: no caveat.
    let quartz = substrate("st-x-quartz");
    let f0 = quartz.phase_velocity_free_m_per_s / 400e-6;
    assert!(
        paper_idt()
            .admittance(&quartz, f0)
            .unwrap()
            .caveats
            .is_empty()
    );
}

#[test]
fn finger_resistance_is_lakins_lumped_two_thirds_over_np() {
    let idt = Idt {
        metallisation: Some(Metallisation {
            metal: ElectrodeMetal::Aluminium,
            thickness_m: 200e-9,
        }),
        ..paper_idt()
    };
    let finger = 2.65e-8 * 9e-3 / (100e-6 * 200e-9);
    assert!((idt.finger_resistance_ohm() / finger - 1.0).abs() < 1e-14);
    assert!((idt.series_resistance_ohm() / (2.0 * finger / 60.0) - 1.0).abs() < 1e-14);
    let sub = substrate("128yx-linbo3");
    let lossy = idt.drive(&sub, 125.0, 9.61e6).unwrap();
    let ideal = paper_idt().drive(&sub, 125.0, 9.61e6).unwrap();
    assert!(lossy.ohmic_power_w > 0.0 && ideal.ohmic_power_w == 0.0);
    assert!(lossy.acoustic_power_w < ideal.acoustic_power_w);
    assert!(lossy.transducer_voltage_peak_v < 125.0);
    assert!((ideal.transducer_voltage_peak_v / 125.0 - 1.0).abs() < 1e-14);
}

#[test]
fn stress_free_permittivity_of_linbo3_is_near_the_measured_values() {
    // Crystal axes. Measured ε^T/ε₀ of LiNbO3: 84.6 (ε11) and 28.7 (ε33) (Warner, Onoe &
    // Coquin 1967); ε^T computed from each constant set's ε^S, e and c^E must land within 5 %
    // (a set's own measured ε^S and ε^T are not mutually consistent beyond that).
    for material in [
        materials::lithium_niobate_kovacs_1990(),
        materials::lithium_niobate_warner_1967(),
    ] {
        let eps = material.permittivity_stress_free_f_per_m().unwrap();
        let (e11, e33) = (
            eps[0][0] / VACUUM_PERMITTIVITY_F_PER_M,
            eps[2][2] / VACUUM_PERMITTIVITY_F_PER_M,
        );
        assert!(
            (e11 / 84.6 - 1.0).abs() < 0.05,
            "{}: ε11^T/ε0 = {e11}",
            material.name
        );
        assert!(
            (e33 / 28.7 - 1.0).abs() < 0.05,
            "{}: ε33^T/ε0 = {e33}",
            material.name
        );
        assert!(
            (eps[1][1] / eps[0][0] - 1.0).abs() < 1e-12,
            "trigonal ε22 = ε11"
        );
    }
    let sub = substrate("128yx-linbo3");
    assert!(sub.effective_permittivity_clamped_f_per_m < sub.effective_permittivity_f_per_m);
}

#[test]
fn bad_fields_are_refused_with_their_names() {
    let sub = substrate("128yx-linbo3");
    let field_of = |idt: Idt, volts: f64, hz: f64| match idt.drive(&sub, volts, hz) {
        Err(WaveError::InvalidIdt { field, .. }) => field,
        other => panic!("expected InvalidIdt, got {other:?}"),
    };
    let good = paper_idt;
    assert_eq!(
        field_of(
            Idt {
                finger_pairs: 0,
                ..good()
            },
            125.0,
            9.6e6
        ),
        "finger_pairs"
    );
    for bad in [0.0, -1e-6, f64::NAN, f64::INFINITY] {
        assert_eq!(
            field_of(
                Idt {
                    finger_width_m: bad,
                    ..good()
                },
                125.0,
                9.6e6
            ),
            "finger_width_m"
        );
        assert_eq!(
            field_of(
                Idt {
                    gap_m: bad,
                    ..good()
                },
                125.0,
                9.6e6
            ),
            "gap_m"
        );
        assert_eq!(
            field_of(
                Idt {
                    aperture_m: bad,
                    ..good()
                },
                125.0,
                9.6e6
            ),
            "aperture_m"
        );
        assert_eq!(field_of(good(), bad, 9.6e6), "drive_voltage_peak_v");
        assert_eq!(field_of(good(), 125.0, bad), "frequency_hz");
        let film = |metal, thickness_m| Idt {
            metallisation: Some(Metallisation { metal, thickness_m }),
            ..good()
        };
        assert_eq!(
            field_of(film(ElectrodeMetal::Aluminium, bad), 125.0, 9.6e6),
            "metallisation.thickness_m"
        );
        assert_eq!(
            field_of(
                film(
                    ElectrodeMetal::Other {
                        resistivity_ohm_m: bad
                    },
                    1e-7
                ),
                125.0,
                9.6e6
            ),
            "metallisation.resistivity_ohm_m"
        );
    }
    let text = paper_idt()
        .drive(&sub, -3.0, 9.6e6)
        .unwrap_err()
        .to_string();
    assert!(
        text.contains("drive_voltage_peak_v") && text.contains("-3"),
        "{text}"
    );
}

#[test]
fn a_wave_of_another_cut_is_refused() {
    let cut = Cut::from_name("128yx-linbo3").unwrap();
    let other = Cut::from_name("yz-linbo3").unwrap().solve().unwrap();
    let err = IdtSubstrate::new(&cut, &other).unwrap_err();
    assert!(matches!(err, WaveError::MismatchedWave { .. }), "{err}");
    assert!(err.to_string().contains("yz-linbo3"), "{err}");
}

#[test]
fn electrode_metals_are_found_by_name() {
    assert_eq!(
        ElectrodeMetal::from_name(" Al "),
        Some(ElectrodeMetal::Aluminium)
    );
    assert_eq!(
        ElectrodeMetal::from_name("aluminum"),
        Some(ElectrodeMetal::Aluminium)
    );
    assert_eq!(
        ElectrodeMetal::from_name("CR"),
        Some(ElectrodeMetal::Chromium)
    );
    assert_eq!(ElectrodeMetal::from_name("unobtainium"), None);
    for name in ElectrodeMetal::KNOWN_NAMES {
        assert!(ElectrodeMetal::from_name(name).is_some(), "{name}");
    }
}
