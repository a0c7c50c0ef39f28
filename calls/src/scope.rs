//! The variables the scope records, by the manual's names: an axis' (`a0.pos_fb`, HMPL
//! 5.1.1), a group's (`g0.grp_pg_vel`, `g0.carte_pose_cmd[2]`, HMPL 8.1.1), the
//! controller's I/O (`gpi`, `gpo`, HMPL ch. 9) and the system variables
//! (`system_dtest3`, `system_ltest0`, `system_user_table[100]`, HMPL 23.2). Each is a
//! `u32` code in the scope ring (`ipc::scope`), sampled from the cycle's snapshot and the
//! shared data.

use schema::shared::{SharedData, TestValue, TestVar, USER_TABLE_LEN};
use schema::{AxisSnapshot, GroupSnapshot, MAX_AXES, MAX_GROUPS, Snapshot};

type AxisGetter = fn(&AxisSnapshot) -> f64;
type GroupGetter = fn(&GroupSnapshot, usize) -> f64;

/// Axis variables (HMPL tables 5.1.1.x): name, unit, value. Positions are in the axis'
/// units (mm on a linear axis, docs/decisions.md "Scope units").
const AXIS: &[(&str, &str, AxisGetter)] = &[
    ("ref_pos", "mm", |a| a.ref_pos),
    ("ref_vel", "mm/s", |a| a.ref_vel),
    ("ref_acc", "mm/s²", |a| a.ref_acc),
    ("pos_out", "mm", |a| a.pos_out),
    ("vel_out", "mm/s", |a| a.vel_out),
    ("acc_out", "mm/s²", |a| a.acc_out),
    ("pos_offset", "mm", |a| a.pos_offset),
    ("pos_fb", "mm", |a| a.pos_fb),
    ("vel_fb", "mm/s", |a| a.vel_fb),
    ("pos_err", "mm", |a| a.pos_err),
    ("vel_err", "mm/s", |a| a.vel_err),
    ("curr_fb", "A", |a| a.curr_fb),
    ("motion_status", "bits", |a| a.motion_status as f64),
    ("fault_status", "bits", |a| a.fault_status as f64),
    ("last_err", "code", |a| a.last_err as f64),
    ("cmd_num", "count", |a| a.cmd_num as f64),
    ("coe_controlword", "bits", |a| a.coe_controlword as f64),
    ("coe_statusword", "bits", |a| a.coe_statusword as f64),
];

/// Group variables (HMPL table 8.1.1.1); the arrays take `[i]`, X Y Z A B C.
const GROUP: &[(&str, &str, bool, GroupGetter)] = &[
    ("carte_pose_cmd", "mm", true, |g, i| g.carte_pose_cmd[i]),
    ("carte_vel_cmd", "mm/s", true, |g, i| g.carte_vel_cmd[i]),
    ("carte_pose_fb", "mm", true, |g, i| g.carte_pose_fb[i]),
    ("grp_pg_pos", "mm", false, |g, _| g.grp_pg[0]),
    ("grp_pg_vel", "mm/s", false, |g, _| g.grp_pg[1]),
    ("grp_pg_acc", "mm/s²", false, |g, _| g.grp_pg[2]),
    ("motion_status", "bits", false, |g, _| g.motion_status as f64),
    ("fault_status", "bits", false, |g, _| g.fault_status as f64),
];

/// A Cartesian coordinate's unit: A, B, C turn.
fn cartesian_unit(unit: &'static str, element: usize) -> &'static str {
    match (unit, element) {
        ("mm", 3..) => "deg",
        ("mm/s", 3..) => "deg/s",
        _ => unit,
    }
}

const KIND_AXIS: u32 = 1;
const KIND_GROUP: u32 = 2;
const KIND_GPI: u32 = 3;
const KIND_GPO: u32 = 4;
const KIND_DTEST: u32 = 5;
const KIND_LTEST: u32 = 6;
const KIND_USER: u32 = 7;

/// One recorded variable: kind (4 bits), index (20 bits: axis, group, test variable or
/// user-table entry), field (8 bits: the table row, a group array's element in its low 3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Var(u32);

/// A name the scope does not know.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[error(
    "unknown scope variable {0:?}: use aN.<axis variable> (pos_fb, ref_pos, pos_out, pos_err, vel_fb, motion_status, \
     ...), gN.<group variable> (carte_pose_cmd[i], carte_pose_fb[i], grp_pg_vel, ...), gpi, gpo, system_dtestN, \
     system_ltestN or system_user_table[N]"
)]
pub struct UnknownVar(pub String);

impl Var {
    fn new(kind: u32, index: usize, field: usize) -> Var {
        Var(kind << 28 | (index as u32) << 8 | field as u32)
    }

    fn kind(self) -> u32 {
        self.0 >> 28
    }

    fn index(self) -> usize {
        (self.0 >> 8 & 0xF_FFFF) as usize
    }

    fn field(self) -> usize {
        (self.0 & 0xFF) as usize
    }

    /// The ring's code.
    pub fn code(self) -> u32 {
        self.0
    }

    /// A code from the ring; `None` for one this build does not know.
    pub fn from_code(code: u32) -> Option<Var> {
        let var = Var(code);
        let (index, field) = (var.index(), var.field());
        let known = match var.kind() {
            KIND_AXIS => index < MAX_AXES && field < AXIS.len(),
            KIND_GROUP => {
                index < MAX_GROUPS && GROUP.get(field >> 3).is_some_and(|g| field & 7 < if g.2 { 6 } else { 1 })
            }
            KIND_GPI | KIND_GPO => index == 0 && field == 0,
            KIND_DTEST | KIND_LTEST => index < 10 && field == 0,
            KIND_USER => index < USER_TABLE_LEN && field == 0,
            _ => false,
        };
        known.then_some(var)
    }

    /// Parses the manual's name with its axis or group (`a0.pos_fb`).
    pub fn parse(name: &str) -> Result<Var, UnknownVar> {
        let unknown = || UnknownVar(name.to_string());
        let number = |s: &str, below: usize| s.parse::<usize>().ok().filter(|&n| n < below).ok_or_else(unknown);
        // `name[i]` -> (name, Some(i))
        let split_index = |s: &'static str, full: &str| -> Option<Option<String>> {
            let rest = full.strip_prefix(s)?;
            if rest.is_empty() {
                return Some(None);
            }
            rest.strip_prefix('[').and_then(|r| r.strip_suffix(']')).map(|i| Some(i.to_string()))
        };
        let var = if let Some((target, field)) = name.split_once('.') {
            if let Some(axis) = target.strip_prefix('a') {
                let axis = number(axis, MAX_AXES)?;
                let row = AXIS.iter().position(|(n, ..)| *n == field).ok_or_else(unknown)?;
                Var::new(KIND_AXIS, axis, row)
            } else if let Some(group) = target.strip_prefix('g') {
                let group = number(group, MAX_GROUPS)?;
                let (row, element) = GROUP
                    .iter()
                    .enumerate()
                    .find_map(|(row, (n, _, array, _))| match split_index(n, field)? {
                        Some(i) if *array => Some(number(&i, 6).map(|i| (row, i))),
                        None if !*array => Some(Ok((row, 0))),
                        _ => None,
                    })
                    .ok_or_else(unknown)??;
                Var::new(KIND_GROUP, group, row << 3 | element)
            } else {
                return Err(unknown());
            }
        } else if name == "gpi" {
            Var::new(KIND_GPI, 0, 0)
        } else if name == "gpo" {
            Var::new(KIND_GPO, 0, 0)
        } else if let Some(i) = name.strip_prefix("system_dtest") {
            Var::new(KIND_DTEST, number(i, 10)?, 0)
        } else if let Some(i) = name.strip_prefix("system_ltest") {
            Var::new(KIND_LTEST, number(i, 10)?, 0)
        } else if let Some(Some(i)) = split_index("system_user_table", name) {
            Var::new(KIND_USER, number(&i, USER_TABLE_LEN)?, 0)
        } else {
            return Err(unknown());
        };
        Ok(var)
    }

    /// The name `parse` takes.
    pub fn name(self) -> String {
        let (index, field) = (self.index(), self.field());
        match self.kind() {
            KIND_AXIS => format!("a{index}.{}", AXIS[field].0),
            KIND_GROUP => {
                let (name, _, array, _) = GROUP[field >> 3];
                if array { format!("g{index}.{name}[{}]", field & 7) } else { format!("g{index}.{name}") }
            }
            KIND_GPI => "gpi".into(),
            KIND_GPO => "gpo".into(),
            KIND_DTEST => format!("system_dtest{index}"),
            KIND_LTEST => format!("system_ltest{index}"),
            _ => format!("system_user_table[{index}]"),
        }
    }

    /// The value's unit, one plot panel each.
    pub fn unit(self) -> &'static str {
        let field = self.field();
        match self.kind() {
            KIND_AXIS => AXIS[field].1,
            KIND_GROUP => cartesian_unit(GROUP[field >> 3].1, field & 7),
            KIND_GPI | KIND_GPO => "bits",
            _ => "value",
        }
    }

    /// This cycle's value (no allocation: the RT thread calls it).
    pub fn sample(self, snapshot: &Snapshot, shared: &SharedData) -> f64 {
        let (index, field) = (self.index(), self.field());
        match self.kind() {
            KIND_AXIS => AXIS[field].2(&snapshot.axes[index]),
            KIND_GROUP => GROUP[field >> 3].3(&snapshot.groups[index], field & 7),
            KIND_GPI => snapshot.gpio.gpi as f64,
            KIND_GPO => snapshot.gpio.gpo as f64,
            KIND_DTEST | KIND_LTEST => {
                let var = if self.kind() == KIND_DTEST { TestVar::D(index) } else { TestVar::L(index) };
                match shared.test_var(var) {
                    Some(TestValue::Int(v)) => v as f64,
                    Some(TestValue::Double(v)) => v,
                    None => f64::NAN,
                }
            }
            _ => shared.user_table(index).unwrap_or(f64::NAN),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_parses_back_to_itself() {
        let names = [
            "a0.pos_fb",
            "a95.motion_status",
            "a3.ref_pos",
            "g0.carte_pose_cmd[0]",
            "g15.carte_pose_fb[5]",
            "g1.grp_pg_vel",
            "gpi",
            "gpo",
            "system_dtest9",
            "system_ltest0",
            "system_user_table[511999]",
        ];
        for name in names {
            let var = Var::parse(name).unwrap();
            assert_eq!(var.name(), name);
            assert_eq!(Var::from_code(var.code()), Some(var), "{name}");
        }
        assert_eq!(Var::parse("g0.carte_pose_cmd[4]").unwrap().unit(), "deg");
        assert_eq!(Var::parse("a1.vel_fb").unwrap().unit(), "mm/s");
    }

    #[test]
    fn unknown_names_are_refused() {
        for name in [
            "a96.pos_fb",
            "a0.pos",
            "g0.carte_pose_cmd",
            "g0.carte_pose_cmd[6]",
            "g0.grp_pg_vel[0]",
            "system_dtest10",
            "system_user_table[512000]",
            "pos_fb",
        ] {
            assert!(Var::parse(name).is_err(), "{name}");
        }
        assert_eq!(Var::from_code(0), None);
    }
}
