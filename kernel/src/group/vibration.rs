//! HMPL 15.8 to 15.10: a group's input shaper, one per MCS coordinate after the group's
//! smoothing, so that the path's shape is kept (every coordinate is delayed alike). The
//! axes' own shapers are not on this path: a synced axis takes the group's reference
//! as it comes (HMPL 15.1).

use api::{ErrorCode, GroupError};

use crate::shaping::{SHAPER_NORMAL, SHAPER_ROBUST, ShaperParams};

impl super::Group {
    /// The group's shapers are on.
    pub fn in_shape(&self) -> bool {
        self.shapers[0].is_enabled()
    }

    pub(super) fn shapers_settled(&self) -> bool {
        self.shapers.iter().all(|s| s.settled())
    }
}

impl crate::Kernel {
    /// Group `group`'s shapers, once it stands (HMPL 15.8-15.10: "not while moving").
    fn group_at_rest(&mut self, group: i64) -> Result<usize, ErrorCode> {
        let g = self.group_id(group)?;
        if self.groups[g as usize].is_moving() {
            return Err(self.refuse_group(g, GroupError::CmdInvalidMoving));
        }
        Ok(g as usize)
    }

    /// EnableGrpInShape, DisableGrpInShape.
    pub fn switch_group_shaper(&mut self, group: i64, on: bool) -> Result<(), ErrorCode> {
        let g = self.group_at_rest(group)?;
        let grp = &mut self.groups[g];
        let pose = grp.pose_cmd.pos;
        for (shaper, &p) in grp.shapers.iter_mut().zip(&pose) {
            shaper.set_enabled(on, p);
        }
        Ok(())
    }

    /// SetGrpInShape; the registry has checked frequency and damping.
    pub fn set_group_shaper(
        &mut self,
        group: i64,
        freq_hz: f64,
        damping: f64,
        shaper_type: i64,
    ) -> Result<(), ErrorCode> {
        let g = self.group_at_rest(group)?;
        let robust = match shaper_type {
            SHAPER_NORMAL => false,
            SHAPER_ROBUST => true,
            _ => return Err(self.refuse_group(g as u8, GroupError::CmdInvalidInputshapingParameterIncomplete)),
        };
        let params = ShaperParams { freq_hz, damping, robust };
        if !self.groups[g].shapers[0].fits(params) {
            // The room reserved at start-up holds every shaper of HMPL 15.10's ranges.
            return Err(self.refuse_group(g as u8, GroupError::CmdInvalidFrequency));
        }
        let grp = &mut self.groups[g];
        let pose = grp.pose_cmd.pos;
        for (shaper, &p) in grp.shapers.iter_mut().zip(&pose) {
            shaper.configure(params);
            shaper.rest_at(p);
        }
        Ok(())
    }
}
