//! The Fatek FBs-PLC FUN147 (MHSPO) instruction: multi-axis linear interpolation from a
//! step table held in registers.
