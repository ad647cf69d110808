//! Walking on sparse foothold locations (thesis 5.9, 7.3.2): the local
//! map of the footholds an actor's memory holds ([`map`]).

pub mod map;
