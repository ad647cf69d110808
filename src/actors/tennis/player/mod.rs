//! The tennis player, `play_tennis` (thesis 5.6, figures 5.6.1–5.6.3):
//! a racket-like actor that sees the ball and its partner by colour
//! (vision), hears the collisions and the referee (audition), and keeps
//! the state of its game (`tennis_state`, table B6). Its eye is the
//! racket's centre; the racket moves along the timed spline of 5.6.6.
//!
//! The player perceives only: the ball's position from its window's
//! pixels (eq. 3.1.9), its velocity from three frames of them (eq.
//! 5.6.1), the referee's words and the ball's collisions from the sounds
//! it hears. What it does to the world is its racket's motion (its eye,
//! which `C` par1 = 5 carries into the physics) and, as the server, the
//! toss ([`Deed::Toss`]). docs/tennis.md has the readings chosen.

use glam::{DVec3, Vec3};

use super::call::word::{BLUE, EXIT, FAULT, GREEN, LEFT, LET, RIGHT, SERVICE};
use super::court::{court, service_box, side_of, Half, Side, BALL_LOW, BASE_LINE};
use super::ears::Ears;
use super::eyes::{player_thing, Sightings, BALL};
use super::hit::{aim_point, hit, Aim, RacketHit, Shot};
use super::impact::{
    after_bounce, choose_impact, estimate_impact, horizontal, impact_delay, rising_impact,
    velocity_now, Impact, Learner,
};
use super::racket_path::{RacketPath, StrokePlan};
use crate::actors::behaviour::{is_voice, Behaviour, Deed, Senses};
use crate::lsys::automata::{Automata, AutomataCommand};

/// `tennis_state` values (table B6).
pub mod game {
    pub const INACTIVE: i64 = 0;
    pub const GOTO_PLAY_POSITION: i64 = 1;
    pub const LOOK_FOR_PARTNER: i64 = 2;
    pub const PARTNER_OK: i64 = 3;
    pub const FOLLOW_BALL: i64 = 4;
    pub const FIRST_HIT_TURN: i64 = 5;
    pub const HIT_TURN: i64 = 8;
    pub const BOUNCE_OR_NOT_BOUNCE: i64 = 9;
    pub const BOUNCE: i64 = 10;
    pub const BOUNCE_BEGIN: i64 = 11;
    pub const NOT_BOUNCE: i64 = 12;
    pub const HIT_PHASE: i64 = 13;
}
use game::*;

mod play_tennis;

/// The collision sounds of table D.1 the player listens to.
const BALL_RACKET: u32 = 0;
const BALL_GROUND: u32 = 1;

/// Gravity the players reckon with (m/s², the scenes' `?18`).
const G: f64 = 9.81;
/// The height the racket meets the ball at (eq. 5.6.2's h), in a rally
/// and on a service (the toss is struck above the head).
const HIT_HEIGHT: f64 = 1.0;
const SERVE_HEIGHT: f64 = 2.6;
/// Eq. 5.6.1's n, and impact estimation every 4th frame (5.6.2), until
/// the ball is within 1 m of the impact point.
const VELOCITY_FRAMES: u32 = 3;
const ESTIMATE_EVERY: u64 = 4;
const STOP_ESTIMATING: f64 = 1.0;
/// The racket's stroke (5.6.6): straight for up to `HIT_LENGTH` on each
/// side of the impact, back at its start `RETURN_TIME` after it; the
/// impact is key point `MIDDLE`.
const HIT_LENGTH: f64 = 1.5;
const RETURN_TIME: f64 = 1.0;
const MIDDLE: usize = 4;
/// An elastic racket field of infinite mass sends the ball off at
/// R(v) + 2c (docs/tennis.md): the racket moves at half eq. 5.6.14's c
/// so that the ball leaves with the wished a = R(v) + c.
const FIELD_GAIN: f64 = 2.0;
/// Where the players wait: behind the base line, and on a service half
/// a metre from the centre mark (server) or in the box's middle
/// (receiver).
const BEHIND: f64 = 1.0;
const SERVER_FROM_CENTRE: f64 = 0.8;
/// The aim's margins inside the base line and the side lines: the depth
/// of the strokes scatters about 2 m, their side much less (docs/tennis.md),
/// and the service's aim, this far in front of the service line.
const AIM_DEEP: f64 = 3.5;
const AIM_WIDE: f64 = 2.0;
const SERVE_SHORT: f64 = 1.2;
/// The toss: from in front of the server, straight up.
const TOSS_AHEAD: f64 = 1.0;
const TOSS_HEIGHT: f64 = 1.2;
const TOSS_SPEED: f64 = 6.0;
/// A server that has not struck its toss this long after tosses again.
const TOSS_PATIENCE: f64 = 2.5;
/// A server waits this long once ready, and looks for its partner at
/// most `PARTNER_PATIENCE` before it plays anyway.
const SERVE_PAUSE: f64 = 0.6;
const PARTNER_PATIENCE: f64 = 3.0;
/// A partner within this of its start point is ready (look_for_partner).
const PARTNER_NEAR: f64 = 2.5;
/// The ball's diameter as the players know it, and how many pixels wide
/// their search makes it.
const BALL_SIZE: f64 = 0.2;
const SEARCH_PIXELS: f64 = 3.0;
/// How far from its start a player goes for the ball (horizontally).
const REACH: f64 = 8.0;
/// Below this height the ball is about to bounce (bounce_begin).
const BOUNCE_BEGINS: f64 = 0.5;
/// A ball landing this far outside the player's court is let go.
const LET_GO: f64 = 1.0;

/// What vision is busy with (figure 5.6.3): the ball, or a glance at the
/// partner.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Focus {
    Thing,
    Partner,
}

/// A planned stroke.
#[derive(Debug, Clone)]
struct Stroke {
    impact: Impact,
    path: RacketPath,
    /// The aim it was planned for, the ball's wished velocity, and
    /// whether it is a service.
    aim: DVec3,
    wished: DVec3,
    serve: bool,
}

/// What a player keeps between frames.
#[derive(Debug, Clone)]
pub struct Player {
    pub side: Side,
    /// Where it waits for the ball, and where its partner does.
    pub start: DVec3,
    opponent_start: DVec3,
    /// The server of the point in play.
    server: Option<Side>,
    /// `interpret_words`: `listen` is capturing the server and its half.
    interpret: bool,
    focus: Focus,
    /// Since when it looks for its partner, and since when it is ready.
    looking_since: Option<f64>,
    ready_since: Option<f64>,
    ball: Sightings,
    /// Eq. 5.6.1's velocity, derived every third frame.
    velocity: Option<DVec3>,
    frames: u64,
    learner: Learner,
    rally: Aim,
    service: Aim,
    aim: DVec3,
    stroke: Option<Stroke>,
    /// Where the ball was, how fast, when entering bounce_or_not_bounce
    /// (eq. 5.6.6's P₁, v, t₁).
    first_sight: Option<(DVec3, DVec3, f64)>,
    /// Its last stroke, until it learns where the ball landed.
    shot: Option<(Shot, bool)>,
    /// The ball as its last stroke sent it: from where, when, how fast
    /// (the wished velocity a): where its eyes look for it.
    sent: Option<(DVec3, f64, DVec3)>,
    ears: Ears,
    /// Where and when it tossed the ball for its service.
    tossed: Option<(DVec3, f64)>,
    /// Its strokes in the point: the first is a service or a return.
    strokes: u32,
    /// When the ball bounced on its side since the last stroke heard.
    bounced: Option<f64>,
    /// Whether the partner's stroke was heard since its own.
    partner_struck: bool,
    /// The ball's side of the net at the last sighting.
    ball_side: Option<Side>,
}

impl Player {
    fn new(side: Side) -> Self {
        let start = rally_spot(side);
        Player {
            side,
            start,
            opponent_start: rally_spot(side.opponent()),
            server: None,
            interpret: false,
            focus: Focus::Thing,
            looking_since: None,
            ready_since: None,
            ball: Sightings::default(),
            velocity: None,
            frames: 0,
            learner: Learner::default(),
            rally: Aim {
                c1: 5.0,
                c2: 0.75,
                inclination: 0.25,
            },
            service: Aim {
                c1: 5.0,
                c2: 0.92,
                inclination: 0.05,
            },
            aim: aim_point(rally_spot(side.opponent()), AIM_DEEP, AIM_WIDE),
            stroke: None,
            first_sight: None,
            shot: None,
            sent: None,
            ears: Ears::default(),
            tossed: None,
            strokes: 0,
            bounced: None,
            partner_struck: false,
            ball_side: None,
        }
    }

    fn is_server(&self) -> bool {
        self.server == Some(self.side)
    }

    /// The point is over: no stroke is pending any more.
    fn end_point(&mut self) {
        self.server = None;
        self.tossed = None;
        self.strokes = 0;
        self.stroke = None;
        self.bounced = None;
        self.sent = None;
        self.partner_struck = false;
        self.first_sight = None;
        self.ready_since = None;
        self.looking_since = None;
    }
}

/// The sign of x on a side of the net.
fn x_sign(side: Side) -> f64 {
    match side {
        Side::Green => -1.0,
        Side::Blue => 1.0,
    }
}

/// Where a player waits in a rally: behind the middle of its base line,
/// at the hitting height.
fn rally_spot(side: Side) -> DVec3 {
    DVec3::new(x_sign(side) * (BASE_LINE + BEHIND), HIT_HEIGHT, 0.0)
}

/// Where the server stands (next to the centre mark, on the half it
/// serves from) and where the receiver waits (behind the box's middle).
fn service_spots(server: Side, half: Half) -> [DVec3; 2] {
    let target = service_box(server, half);
    let box_z = 0.5 * (target.z[0] + target.z[1]);
    // The server stands diagonally opposite the box's middle.
    let server_z = -box_z.signum() * SERVER_FROM_CENTRE;
    [
        DVec3::new(x_sign(server) * (BASE_LINE + BEHIND), HIT_HEIGHT, server_z),
        DVec3::new(-x_sign(server) * (BASE_LINE + BEHIND), HIT_HEIGHT, box_z),
    ]
}

/// The service's aim: the middle of the box, `SERVE_SHORT` before its
/// service line.
fn service_aim(server: Side, half: Half) -> DVec3 {
    let b = service_box(server, half);
    let far = if b.x[1].abs() > b.x[0].abs() {
        b.x[1]
    } else {
        b.x[0]
    };
    DVec3::new(
        far - SERVE_SHORT * far.signum(),
        0.0,
        0.5 * (b.z[0] + b.z[1]),
    )
}

/// The ball's velocity at the impact, predicted without air damping:
/// the same horizontal run, gravity on the vertical part.
fn velocity_at(v: DVec3, now: f64, impact: &Impact) -> DVec3 {
    DVec3::new(v.x, v.y - G * (impact.time - now), v.z)
}

impl Player {
    /// Whether the ball flies toward it, from the net's side of it,
    /// since it heard its partner strike.
    fn coming(&self) -> bool {
        let sign = x_sign(self.side);
        if !self.partner_struck {
            return false;
        }
        let ahead = self
            .ball
            .last()
            .is_some_and(|(_, b)| b.x * sign < self.start.x * sign);
        ahead && self.velocity.is_some_and(|v| v.x * sign > 1.0)
    }

    /// Whether the ball has gone: past it beyond its reach, or flying
    /// back over the net (not its own toss).
    fn gone(&self) -> bool {
        let sign = x_sign(self.side);
        let Some((_, b)) = self.ball.last() else {
            return false;
        };
        let past = b.x * sign > self.start.x * sign + REACH;
        let back = self.velocity.is_some_and(|v| v.x * sign < -1.0) && b.x * sign < 0.0;
        past || back
    }

    /// Eq. 5.6.6: learns x from the first sighting and this one.
    fn learn_x(&mut self, at: DVec3, t: f64) {
        if let Some((p1, v1, t1)) = self.first_sight.take() {
            self.learner.learn(p1, v1, t1, at, t);
        }
    }

    /// Whether a ball seen at `at` with velocity `v` at `t` lands in
    /// the player's court (a margin outside counts in).
    fn side_ok(&self, at: DVec3, v: DVec3, t: f64) -> bool {
        let Some(landing) = estimate_impact(at, v, t, 0.0, G, 1.0) else {
            return true;
        };
        let c = court(self.side);
        let l = landing.point;
        let inside = |x: f64, r: [f64; 2]| x >= r[0] - LET_GO && x <= r[1] + LET_GO;
        inside(l.x, c.x) && inside(l.z, c.z)
    }

    /// Plans the stroke at `impact` (5.6.4–5.6.6): the wished velocity
    /// toward the aim, the racket's velocity, its timed path.
    fn plan(&mut self, racket: DVec3, now: f64, impact: Impact, v: DVec3, serve: bool) {
        if horizontal(impact.point - self.start).length() > REACH {
            // Out of its reach: it keeps the plan it has, if any.
            return;
        }
        let aim = if serve { &self.service } else { &self.rally };
        let a = aim.velocity(impact.point, self.aim);
        let RacketHit { normal, speed } = hit(v, a);
        let velocity = self
            .stroke
            .as_ref()
            .map_or(DVec3::ZERO, |s| s.path.at(now).1);
        let plan = StrokePlan {
            now,
            position: racket,
            velocity,
            impact,
            hit: RacketHit {
                normal,
                speed: speed / FIELD_GAIN,
            },
            hit_length: HIT_LENGTH,
            return_time: RETURN_TIME,
            start: self.start,
            opponent_start: self.opponent_start,
            middle: MIDDLE,
        };
        if let Some(path) = RacketPath::plan(&plan) {
            self.stroke = Some(Stroke {
                impact,
                path,
                aim: self.aim,
                wished: a,
                serve,
            });
        }
    }
}
