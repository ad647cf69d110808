//! Walking on sparse foothold locations (thesis 5.9, 7.3.2): the local
//! map of the footholds an actor's memory holds ([`map`]), the optimal
//! steps over them ([`plan`]), and the automata `walk_stepworthy` that
//! looks, maps, plans and walks ([`walk`]).

pub mod map;
pub mod plan;
pub mod walk;
