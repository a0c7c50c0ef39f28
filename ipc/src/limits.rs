//! Who attaches to one controller. Every limit of every service is derived from these few
//! numbers; iceoryx2's defaults (20 nodes per publish-subscribe service) would stop the
//! 20th script.

use schema::MAX_TASKS;

/// Processes of one task at a time on the soak floor's wake events (`wake`): a restarted
/// side opens its port while the dead one's may still be being cleaned up.
pub const PROCESSES_PER_TASK: usize = 2;
/// Tools attached to a controller at once, each a node of its own: `luamotion tasks`,
/// `luamotion events`, the soak's monitor, the DRL console, the start-up probe, and at
/// least 4 more monitors, with room to spare.
pub const MAX_TOOLS: usize = 12;
/// Idle script processes the supervisor keeps ready (`[rt] script_pool`), each a node.
pub const MAX_POOL: usize = 4;
/// Of those, the ones that follow the event stream at once (`luamotion events`, monitors).
pub const MAX_EVENT_READERS: usize = 8;
/// Nodes of the controller process itself: the core's, the supervisor's.
const CONTROLLER_NODES: usize = 2;
/// Nodes of the service every process opens (`events`). A dead process' node is cleaned
/// when the next one opens the service, so each task counts once.
pub const MAX_NODES: usize = CONTROLLER_NODES + MAX_TASKS + MAX_POOL + MAX_TOOLS;
/// Records a reader may fall behind one writer by before the oldest are dropped: more
/// than a task's burst of events (100) or the supervisor's alarms when all 64 tasks fail
/// at once. Each writer's segment holds this many per reader.
pub const EVENT_BUFFER: usize = 128;
/// Records a reader that joins late still sees.
pub const EVENT_HISTORY: usize = 16;
/// Records a reader holds at once (it copies each out).
pub const EVENT_BORROWED: usize = 2;
