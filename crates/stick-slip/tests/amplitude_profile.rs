//! The amplitude along x: with the tabulated profile in place, the exponential decay path and
//! the constant wave give the same bits as before it existed (reference bits computed at commit
//! 5758a52, before `crate::attenuation`).

#[path = "support/johnson.rs"]
mod johnson;

use stick_slip::{
    DynamicScene, Integrator, ModelChoice, PeriodicAverageModel, TransientModel, TransientRun,
    TransientStart,
};

fn decaying_scene() -> DynamicScene {
    let (k_n, k_t) = johnson::springs(10e-6);
    let mut scene = DynamicScene::paper_default(k_n, k_t);
    scene.model = ModelChoice::Transient;
    scene.wave.decay_length_m = Some(8e-3);
    scene.options.transient.periods = 12.0;
    scene.options.transient.average_periods = 6.0;
    scene
}

/// Speed, thrust, stator power and mean tip height of a run, as bits.
fn bits(run: &TransientRun) -> [u64; 4] {
    [
        run.speed_m_per_s.to_bits(),
        run.thrust_n.to_bits(),
        run.stator_power_w.to_bits(),
        run.mean_tip_height_m.to_bits(),
    ]
}

#[test]
fn exponential_decay_transient_is_bit_identical_to_before_the_profile() {
    let scene = decaying_scene();
    let run = TransientModel::new(&scene)
        .unwrap()
        .run(3.0, TransientStart::Estimate, false)
        .unwrap();
    assert_eq!(
        bits(&run),
        [
            4603915416463314539,
            4613772415388654248,
            4614853409943888066,
            4466752252763788053
        ],
        "return-mapping run with decay_length (speed, thrust, stator power, tip height)"
    );
    let mut exact = scene.clone();
    exact.integrator = Integrator::EventDriven { max_step_s: None };
    exact.options.transient.periods = 3.0;
    exact.options.transient.average_periods = 2.0;
    let run = TransientModel::new(&exact)
        .unwrap()
        .run(3.0, TransientStart::Estimate, false)
        .unwrap();
    assert_eq!(
        bits(&run),
        [
            4603939944513663616,
            4613576495429132425,
            4614563697582521580,
            4466752252763788299
        ],
        "event-driven run with decay_length (speed, thrust, stator power, tip height)"
    );
}

#[test]
fn constant_wave_transient_and_period_average_are_bit_identical_to_before_the_profile() {
    let mut scene = decaying_scene();
    scene.wave.decay_length_m = None;
    let run = TransientModel::new(&scene)
        .unwrap()
        .run(3.0, TransientStart::Estimate, false)
        .unwrap();
    assert_eq!(
        bits(&run),
        [
            4603947677407433554,
            4613937510525678010,
            4613774690008579839,
            4464148980687774470
        ],
        "return-mapping run of the constant wave"
    );
    let periodic = PeriodicAverageModel::new(&scene).unwrap();
    let expected = [
        (0.0, [4622666381934032442u64, 4621942151842804167u64]),
        (0.3, [4621472013073688929, 4621126368657985931]),
    ];
    for (v, reference) in expected {
        let s = periodic.at_speed(v).unwrap();
        assert_eq!(
            [s.thrust_n.to_bits(), s.stator_power_w.to_bits()],
            reference,
            "period average at {v} m/s (thrust, stator power)"
        );
    }
}
