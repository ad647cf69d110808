//! The vision states shared by the players and the referee (5.6.1,
//! 5.7): look for the thing of interest with a 40° view
//! (look_around_set, then look_around: the eyes turn half a view a
//! frame), then follow it (fix_thing / focus_thing), zooming by 1.5 to
//! keep it between 5 and 12 pixels; lost, look for it again. Apart from
//! `eyes.rs`, which the players' and referee's types import, so that the
//! actor's state and its tennis parts import no circle (issue 55).

use glam::Vec3;

use crate::actors::live::Living;
use crate::actors::perception::vision::Found;
use crate::actors::state::{FIX_THING, LOOK_AROUND};

/// The view angle a search starts with (40°), and the narrowest and
/// widest it zooms to, in tenths of a degree.
const SEARCH_FOV: i64 = 400;
const MIN_FOV: i64 = 20;
const MAX_FOV: i64 = 1200;
/// Vision keeps the thing it follows between these many pixels, zooming
/// by 1.5 (5.6.1).
const MIN_PIXELS: u32 = 5;
const MAX_PIXELS: u32 = 12;
const ZOOM: f64 = 1.5;

impl Living {
    /// One frame of the vision states: the thing of interest when the
    /// window shows it (the eyes then fix it, `lead` ahead of where it is
    /// — where it will be at the next frame — and zoom), else the search.
    pub(in crate::actors) fn follow_thing(&mut self, lead: Vec3) -> Option<Found> {
        match self.percepts.as_ref().and_then(|p| p.thing) {
            Some(thing) => {
                self.state = FIX_THING;
                self.look_at = thing.position + lead;
                if thing.pixels < MIN_PIXELS {
                    self.fov = ((self.fov as f64 / ZOOM) as i64).max(MIN_FOV);
                } else if thing.pixels > MAX_PIXELS {
                    self.fov = ((self.fov as f64 * ZOOM) as i64).min(MAX_FOV);
                }
                Some(thing)
            }
            None if self.state == LOOK_AROUND => {
                self.turn_eyes(self.half_view());
                None
            }
            None => {
                self.look_around_set();
                None
            }
        }
    }

    /// look_around_set: a 40° view, and look_around next.
    pub(in crate::actors) fn look_around_set(&mut self) {
        self.state = LOOK_AROUND;
        self.fov = SEARCH_FOV;
    }
}
