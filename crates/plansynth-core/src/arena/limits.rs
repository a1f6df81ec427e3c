//! The limits of one call on the game (a deadline, a memory limit checked against the
//! bytes the game holds, a cap on configurations) and why a call stopped.

use std::time::Instant;

use super::Arena;

/// The limits of one call: a deadline, a memory limit (bytes), a configuration cap.
#[derive(Clone, Debug, Default)]
pub struct Budget {
    pub deadline: Option<Instant>,
    pub memory: Option<usize>,
    pub max_configs: Option<usize>,
}

/// Why exploration or induction stopped.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Stop {
    Time {
        step: usize,
        configs: usize,
    },
    Memory {
        step: usize,
        configs: usize,
        bytes: usize,
    },
    Configs {
        configs: usize,
    },
}

impl Arena {
    pub(super) fn check(
        &self,
        clock: &Budget,
        step: usize,
        configs: usize,
        extra: usize,
    ) -> Result<(), Stop> {
        if clock.deadline.is_some_and(|d| Instant::now() >= d) {
            return Err(Stop::Time { step, configs });
        }
        if let Some(limit) = clock.memory {
            let bytes = self.bytes() + extra;
            if bytes > limit {
                return Err(Stop::Memory {
                    step,
                    configs,
                    bytes,
                });
            }
        }
        Ok(())
    }
}
