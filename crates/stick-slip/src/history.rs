//! Time histories: one post's normal and tangential force with its stick/slip state (the
//! paper's Fig. 6), and the slider's motion in a transient run.

use serde::Serialize;

/// Contact state of a post at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContactState {
    /// No contact.
    Separated,
    /// Stuck to the stator surface.
    Stick,
    /// Sliding.
    Slip,
}

impl From<crate::post::Mode> for ContactState {
    fn from(mode: crate::post::Mode) -> Self {
        match mode {
            crate::post::Mode::Separated => Self::Separated,
            crate::post::Mode::Stick => Self::Stick,
            crate::post::Mode::Slip(_) => Self::Slip,
        }
    }
}

/// Forces on one post over time. Tangential force and stator velocity are along the drive
/// direction (−x): positive tangential force pushes the slider the way it moves.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct PostHistory {
    /// Slider speed along the drive direction during the history (m/s), mean for a transient.
    pub speed_m_per_s: f64,
    /// Sample times (s), from the start of the shown window.
    pub time_s: Vec<f64>,
    /// Normal force on the post (N).
    pub normal_force_n: Vec<f64>,
    /// Tangential force on the slider from the post, along the drive direction (N).
    pub tangential_force_n: Vec<f64>,
    /// Friction bound μ_k N along the drive direction (N), for reference.
    pub friction_bound_n: Vec<f64>,
    /// Stator surface tangential velocity under the post, along the drive direction (m/s).
    pub stator_velocity_m_per_s: Vec<f64>,
    /// Contact state at each sample.
    pub state: Vec<ContactState>,
    /// Time intervals (s) in which the post sticks.
    pub stick_intervals_s: Vec<(f64, f64)>,
}

impl PostHistory {
    /// Drop the samples before `time_s` (s, on the run's clock).
    pub(crate) fn keep_from(&mut self, time_s: f64) {
        let first = self.time_s.partition_point(|&t| t < time_s);
        self.time_s.drain(..first);
        self.normal_force_n.drain(..first);
        self.tangential_force_n.drain(..first);
        self.friction_bound_n.drain(..first);
        self.stator_velocity_m_per_s.drain(..first);
        self.state.drain(..first);
    }

    /// Build `stick_intervals_s` from the sampled states (for sampled schemes).
    pub(crate) fn intervals_from_states(&mut self) {
        let mut intervals = Vec::new();
        let mut open: Option<f64> = None;
        for (i, (&t, &state)) in self.time_s.iter().zip(&self.state).enumerate() {
            match (state == ContactState::Stick, open) {
                (true, None) => {
                    open = Some(if i == 0 {
                        t
                    } else {
                        0.5 * (t + self.time_s[i - 1])
                    })
                }
                (false, Some(start)) => {
                    intervals.push((start, 0.5 * (t + self.time_s[i - 1])));
                    open = None;
                }
                _ => {}
            }
        }
        if let (Some(start), Some(&end)) = (open, self.time_s.last()) {
            intervals.push((start, end));
        }
        self.stick_intervals_s = intervals;
    }
}

/// The slider's motion in a transient run.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct SliderHistory {
    /// Sample times (s) from the start of the run.
    pub time_s: Vec<f64>,
    /// Slider speed along the drive direction (m/s).
    pub speed_m_per_s: Vec<f64>,
    /// Total tangential contact force along the drive direction (N).
    pub thrust_n: Vec<f64>,
    /// Total normal contact force (N).
    pub normal_force_n: Vec<f64>,
    /// Post-tip reference height z_s (m).
    pub tip_height_m: Vec<f64>,
}
