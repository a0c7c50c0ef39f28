pub mod look_ahead;
