//! Axis ownership on the machine (DXMC 9, 0x001F; docs/decisions.md, "Axis ownership"):
//! whose motion an axis runs, for dispatch's refusals, and whom to tell when a stop (a
//! task's, or the console's leaving Run) cuts that motion short. The kernel says who set
//! the motion going (`kernel::ownership`); the machine knows which tasks still run and
//! publishes the alarms.

use api::alarms::Event;
use schema::MAX_AXES;

use crate::tasks::Tasks;
use kernel::Kernel;
use kernel::ownership::is_box;

/// The axes a stop reaches.
pub enum Reach {
    Axis(i64),
    Group(i64),
    All,
}

/// The owner of axis `a`'s motion: a FUN147 box, or a task that still runs (the motion
/// a stopped task leaves going, fault reaction `none`, is no one's).
pub fn motion_owner(kernel: &Kernel, tasks: &Tasks, a: u8) -> Option<u8> {
    kernel.axis_owner(a).filter(|&owner| is_box(owner) || tasks.accepts_commands(owner))
}

/// The tasks other than `by` (`None`: the console) that own the motion of the axes
/// `reach` names, by axis. A box sees a stop itself and errs.
pub fn owners_reached(kernel: &Kernel, tasks: &Tasks, reach: &Reach, by: Option<u8>) -> [Option<u8>; MAX_AXES] {
    let mut owners = [None; MAX_AXES];
    let axes = kernel.axes().len();
    let mut mark = |a: usize| {
        owners[a] = motion_owner(kernel, tasks, a as u8).filter(|&o| Some(o) != by && !is_box(o));
    };
    match *reach {
        Reach::Axis(a) => usize::try_from(a).ok().filter(|&a| a < axes).into_iter().for_each(&mut mark),
        Reach::Group(g) => {
            if let Ok(group) = kernel.group(g) {
                let (members, n) = group.members();
                members[..n].iter().for_each(|&a| mark(a as usize));
            }
        }
        Reach::All => (0..axes).for_each(mark),
    }
    owners
}

/// A stop cut short the motion `owners` (by axis) owned: each such axis records the
/// alarm `0x1AAA001F` as its last error, and the alarm is published as the owner's, so
/// that a program told "in position" where it did not command it can see why.
pub fn tell_owners(kernel: &mut Kernel, tasks: &mut Tasks, cycle: u64, owners: &[Option<u8>; MAX_AXES]) {
    for (a, owner) in owners.iter().enumerate() {
        if let Some(owner) = *owner {
            let alarm = tasks.axis_alarm(owner, a as u8, Event::CommandBufferBusy, cycle);
            kernel.record_interruption(a as u8, alarm);
        }
    }
}
