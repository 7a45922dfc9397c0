//! How the planner searches: the grid, the refinement, the weights of its cost, its seed. The
//! defaults are what the guide's measured tables used; the bench and `pushlab control` change
//! them one flag at a time.

/// How the planner searches (the search itself: the planner's module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlannerConfig {
    /// Sites in the first grid, evenly round the pushable perimeter.
    pub sites: usize,
    /// Directions per site in the first grid, evenly across ±`max_angle_rad`.
    pub angles: usize,
    pub max_angle_rad: f64,
    /// The longest push weighed, metres of pusher travel, and how many lengths along it.
    pub reach_m: f64,
    pub lengths: usize,
    /// Modes refined, rounds of refinement, and samples per mode and round.
    pub elites: usize,
    pub rounds: usize,
    pub samples: usize,
    /// Metres of goal distance a metre of the pusher's way to a push is worth.
    pub way_weight: f64,
    /// Metres of goal distance a metre of pushing is worth (shorter pushes when equal).
    pub push_weight: f64,
    /// How much better another push must be to be taken over the one the pusher is on, metres.
    pub keep_margin_m: f64,
    /// A push must bring the object this much nearer the goal to be made where one that does
    /// is found, metres: a push that gains nothing, repeated because moving elsewhere costs its
    /// way, walks the object off (seen: 4 m past a goal 12 mm away).
    pub least_gain_m: f64,
    /// The seed of the planner's draws.
    pub seed: u64,
    /// A filter on the poses it plans from, for tracking noise ([`crate::control::track`]);
    /// `None`: the poses as given.
    pub track: Option<crate::control::track::TrackConfig>,
    /// Whether the best pushes are weighed again as the first of two ([`super::lookahead`]).
    /// Off: on held-out pairs it cost learning online goals in both engines and the true θ seven
    /// in MuJoCo (the guide's "Two pushes planned together").
    pub lookahead: bool,
    /// Lengths tried for the second push, along `reach_m` as the first's are.
    pub follow_lengths: usize,
}

impl Default for PlannerConfig {
    fn default() -> Self {
        Self {
            sites: 32,
            angles: 7,
            max_angle_rad: 35f64.to_radians(),
            reach_m: 0.12,
            lengths: 30,
            elites: 3,
            rounds: 2,
            samples: 12,
            way_weight: 0.05,
            push_weight: 0.02,
            keep_margin_m: 0.005,
            least_gain_m: 0.001,
            seed: 0,
            track: None,
            lookahead: false,
            follow_lengths: 8,
        }
    }
}

impl PlannerConfig {
    /// This config drawing from stream `stream` of `base`'s seed (`seed = base + stream·2³²`):
    /// stream 0 is the seed the runs were measured with; another stream leaves the object, the
    /// goal and every rule as they are and changes only the planner's own draws, which is how
    /// much of a measured count is the planner's chance (`--planner-seed`).
    pub fn drawing_from(self, base: u64, stream: u64) -> Self {
        Self {
            seed: base.wrapping_add(stream << 32),
            ..self
        }
    }
}
