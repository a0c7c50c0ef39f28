//! The VM's hook, armed only when it is needed. Once a count or line hook is set, Lua 5.4
//! runs `luaG_traceexec` before every instruction, whatever the count: a program with a
//! hook runs 2 to 2.7 times slower than stock Lua (benches/lua_speed.rs). So a running
//! program has no hook, and a watcher thread of the script process arms one by a signal
//! every `SAMPLE_PERIOD` while the task's slot says the program runs Lua, and once when the
//! console brings the debugger news (breakpoints, a command), even while the program waits,
//! so that the hook takes them at its next instruction; the hook
//! (`Debugger::on_event`) records the line for the watchdog's report, bounds the depth,
//! carries out the debugger's work and disarms itself unless the debugger needs lines.
//!
//! `lua_sethook` may be called asynchronously, from a signal handler (Lua 5.4's ldebug.c;
//! lua.c's own SIGINT handler does so). Hooks are per Lua thread, so the handler must arm
//! the coroutine that runs: `coroutine.resume` and `coroutine.wrap` are Lua's own,
//! rewritten to note the running thread around `lua_resume` (which never raises, so the
//! note is always put back) and to hand a hook on between the resumer and the coroutine
//! both ways (a Pause or a step follows the program; the hook takes itself off again
//! where it is not needed).
//!
//! A hang inside one C function call (a pattern match that never ends) is not reached by
//! the hook, which runs between instructions: the watchdog then names the line last
//! sampled before the call (docs/decisions.md, "Watchdog").

use std::ffi::c_int;
use std::marker::PhantomData;
use std::ptr;
use std::sync::Arc;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicUsize, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use mlua::ffi::{self, lua_State};
use mlua::{Lua, Table};

/// How often the watcher arms the hook of a program running Lua: the age of the line the
/// watchdog reports, and how late a Pause or a new breakpoint is seen.
pub const SAMPLE_PERIOD: Duration = Duration::from_millis(10);

thread_local! {
    /// The Lua thread running on this OS thread, while a `Watcher` watches its VM.
    // Const-initialised atomics without a destructor: read from the signal handler
    // without lazy initialisation or locks.
    static RUNNING: AtomicPtr<lua_State> = const { AtomicPtr::new(ptr::null_mut()) };
    /// The hook procedure to arm (mlua's global hook, which calls the debugger); 0: none.
    static HOOK: AtomicUsize = const { AtomicUsize::new(0) };
}

/// The signal the watcher sends to the Lua thread.
fn arm_signal() -> c_int {
    libc::SIGRTMIN() + 4
}

/// The signal handler: arms a count hook that fires at the next instruction of the
/// running Lua thread, unless it has a hook already (the debugger's line hook).
fn on_signal() {
    let hook = HOOK.with(|h| h.load(Ordering::Relaxed));
    let state = RUNNING.with(|r| r.load(Ordering::Relaxed));
    if hook == 0 || state.is_null() {
        return;
    }
    // SAFETY: `HOOK` holds a `lua_Hook` (see `Watcher::start`). `state` is a live Lua
    // thread: the VM's main thread, kept alive by the `Watcher` that set it, or a coroutine
    // during its `lua_resume`, which its resumer's stack keeps alive. `lua_gethookmask`
    // reads one byte; `lua_sethook` is documented as callable asynchronously.
    unsafe {
        let hook: ffi::lua_Hook = std::mem::transmute::<usize, ffi::lua_Hook>(hook);
        if ffi::lua_gethookmask(state) == 0 {
            ffi::lua_sethook(state, Some(hook), ffi::LUA_MASKCOUNT, 1);
        }
    }
}

/// Why the watcher could not start.
#[derive(Debug, thiserror::Error)]
pub enum ArmingError {
    #[error("cannot register the hook's signal: {0}")]
    Signal(std::io::Error),
    #[error("cannot start the watcher thread: {0}")]
    Thread(std::io::Error),
}

/// Arms the hook of the VM running on the thread that started it, every `SAMPLE_PERIOD`
/// while the program runs Lua. Dropped on that thread, before the VM is closed: it stops
/// the watcher thread and forgets the VM.
pub struct Watcher {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
    /// Keeps the main thread `RUNNING` names alive.
    _lua: Lua,
    /// The thread-locals belong to the thread that started the watcher.
    _not_send: PhantomData<*const ()>,
}

impl Watcher {
    /// Starts watching `lua`, whose hook (the debugger's) is installed already.
    /// `make_should_arm` is called on the watcher thread and gives the question asked there
    /// every period: whether to arm the hook now (the program runs Lua: the task's slot
    /// says `Running`; or the debugger has news).
    pub fn start<F, P>(lua: &Lua, make_should_arm: F) -> Result<Watcher, ArmingError>
    where
        F: FnOnce() -> P + Send + 'static,
        P: Fn() -> bool,
    {
        static REGISTERED: OnceLock<Result<(), std::io::ErrorKind>> = OnceLock::new();
        // SAFETY: `on_signal` reads two thread-locals and calls `lua_sethook`, which is
        // async-signal-safe; it allocates nothing and takes no lock.
        let registered = REGISTERED.get_or_init(|| {
            unsafe { signal_hook::low_level::register(arm_signal(), on_signal) }.map(drop).map_err(|e| e.kind())
        });
        (*registered).map_err(|kind| ArmingError::Signal(kind.into()))?;
        let main = lua.current_thread().state();
        // SAFETY: `main` is the VM's main thread, alive while `lua` is.
        let hook = unsafe { ffi::lua_gethook(main) };
        HOOK.with(|h| h.store(hook.map_or(0, |f| f as usize), Ordering::Relaxed));
        RUNNING.with(|r| r.store(main, Ordering::Relaxed));
        // SAFETY: the id of the calling thread, which joins the watcher before it ends.
        let target = unsafe { libc::pthread_self() };
        let stop = Arc::new(AtomicBool::new(false));
        let thread = std::thread::Builder::new()
            .name("lua-watch".into())
            .spawn({
                let stop = stop.clone();
                move || {
                    let should_arm = make_should_arm();
                    while !stop.load(Ordering::Acquire) {
                        std::thread::park_timeout(SAMPLE_PERIOD);
                        if should_arm() && !stop.load(Ordering::Acquire) {
                            // SAFETY: `target` is alive: it joins this thread before it ends.
                            unsafe { libc::pthread_kill(target, arm_signal()) };
                        }
                    }
                }
            })
            .map_err(ArmingError::Thread)?;
        Ok(Watcher { stop, thread: Some(thread), _lua: lua.clone(), _not_send: PhantomData })
    }
}

impl Drop for Watcher {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Release);
        if let Some(thread) = self.thread.take() {
            thread.thread().unpark();
            let _ = thread.join();
        }
        // A signal still on its way finds nothing to arm.
        RUNNING.with(|r| r.store(ptr::null_mut(), Ordering::Relaxed));
        HOOK.with(|h| h.store(0, Ordering::Relaxed));
    }
}

/// The hook mask of the Lua thread running on this OS thread (0: no hook), for tests that
/// prove the hook off; 0 outside a watched VM.
#[cfg(test)]
pub fn running_hook_mask() -> i32 {
    let state = RUNNING.with(|r| r.load(Ordering::Relaxed));
    // SAFETY: as in `on_signal`; read on the Lua thread itself.
    if state.is_null() { 0 } else { unsafe { ffi::lua_gethookmask(state) } }
}

/// Replaces `coroutine.resume` and `coroutine.wrap` with versions that note the running
/// thread (Lua 5.4's lcorolib.c otherwise).
pub fn track_coroutines(lua: &Lua) -> mlua::Result<()> {
    let coroutine: Table = lua.globals().get("coroutine")?;
    // SAFETY: both are Lua C functions that follow the stack discipline of lcorolib.c.
    unsafe {
        coroutine.raw_set("resume", lua.create_c_function(resume)?)?;
        coroutine.raw_set("wrap", lua.create_c_function(wrap)?)?;
    }
    Ok(())
}

/// lcorolib's `auxresume`, with the running thread noted around `lua_resume`. Returns the
/// number of results, or -1 with the error message on top of `l`'s stack. Raises nothing.
unsafe fn resume_noted(l: *mut lua_State, co: *mut lua_State, narg: c_int) -> c_int {
    unsafe {
        if ffi::lua_checkstack(co, narg) == 0 {
            ffi::lua_pushliteral(l, c"too many arguments to resume");
            return -1;
        }
        ffi::lua_xmove(l, co, narg);
        hand_hook_on(l, co);
        let resumer = RUNNING.with(|r| r.swap(co, Ordering::Relaxed));
        let mut nres = 0;
        let status = ffi::lua_resume(co, l, narg, &mut nres);
        RUNNING.with(|r| r.store(resumer, Ordering::Relaxed));
        hand_hook_on(co, l);
        if status == ffi::LUA_OK || status == ffi::LUA_YIELD {
            if ffi::lua_checkstack(l, nres + 1) == 0 {
                ffi::lua_pop(co, nres);
                ffi::lua_pushliteral(l, c"too many results to resume");
                return -1;
            }
            ffi::lua_xmove(co, l, nres);
            nres
        } else {
            ffi::lua_xmove(co, l, 1);
            -1
        }
    }
}

/// Gives `to` the hook of `from` unless it has one: a Pause, a step, a sample or the
/// controller's end follow the program from one thread to the next.
unsafe fn hand_hook_on(from: *mut lua_State, to: *mut lua_State) {
    unsafe {
        let mask = ffi::lua_gethookmask(from);
        if mask != 0 && ffi::lua_gethookmask(to) == 0 {
            ffi::lua_sethook(to, ffi::lua_gethook(from), mask, ffi::lua_gethookcount(from));
        }
    }
}

/// `coroutine.resume(co, ...)`.
unsafe extern "C-unwind" fn resume(l: *mut lua_State) -> c_int {
    unsafe {
        ffi::luaL_checktype(l, 1, ffi::LUA_TTHREAD);
        let co = ffi::lua_tothread(l, 1);
        let r = resume_noted(l, co, ffi::lua_gettop(l) - 1);
        if r < 0 {
            ffi::lua_pushboolean(l, 0);
            ffi::lua_insert(l, -2);
            2
        } else {
            ffi::lua_pushboolean(l, 1);
            ffi::lua_insert(l, -(r + 1));
            r + 1
        }
    }
}

/// `coroutine.wrap(f)`.
unsafe extern "C-unwind" fn wrap(l: *mut lua_State) -> c_int {
    unsafe {
        ffi::luaL_checktype(l, 1, ffi::LUA_TFUNCTION);
        let co = ffi::lua_newthread(l);
        ffi::lua_pushvalue(l, 1);
        ffi::lua_xmove(l, co, 1);
        ffi::lua_pushcclosure(l, wrapped, 1);
        1
    }
}

/// The function `coroutine.wrap` returns: resumes its coroutine, raises its errors.
unsafe extern "C-unwind" fn wrapped(l: *mut lua_State) -> c_int {
    unsafe {
        let co = ffi::lua_tothread(l, ffi::lua_upvalueindex(1));
        let r = resume_noted(l, co, ffi::lua_gettop(l));
        if r >= 0 {
            return r;
        }
        let mut status = ffi::lua_status(co);
        if status != ffi::LUA_OK && status != ffi::LUA_YIELD {
            // An error in the coroutine: close its to-be-closed variables.
            status = ffi::lua_closethread(co, l);
            ffi::lua_xmove(co, l, 1);
        }
        if status != ffi::LUA_ERRMEM && ffi::lua_type(l, -1) == ffi::LUA_TSTRING {
            ffi::luaL_where(l, 1);
            ffi::lua_insert(l, -2);
            ffi::lua_concat(l, 2);
        }
        ffi::lua_error(l)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rewritten functions behave as Lua's own: values through yields, errors with
    /// their position, argument errors.
    #[test]
    fn coroutines_work_as_in_lua() {
        let lua = Lua::new();
        track_coroutines(&lua).unwrap();
        let results: (i64, i64, bool, String, bool, String) = lua
            .load(
                r#"
                local co = coroutine.create(function(a) local b = coroutine.yield(a + 1) return b * 2 end)
                local _, x = coroutine.resume(co, 1)
                local _, y = coroutine.resume(co, 10)
                local dead_ok, dead = coroutine.resume(co)
                local gen = coroutine.wrap(function() error("boom") end)
                local ok, e = pcall(gen)
                local bad_ok = pcall(coroutine.resume, 42)
                return x, y, dead_ok, dead, ok or bad_ok, e
                "#,
            )
            .set_name("=t")
            .eval()
            .unwrap();
        assert_eq!((results.0, results.1), (2, 20));
        assert_eq!((results.2, results.3.as_str()), (false, "cannot resume dead coroutine"));
        assert!(!results.4);
        assert_eq!(results.5, "t:6: boom");
        let sum: i64 = lua
            .load("local f = coroutine.wrap(function() for i = 1, 3 do coroutine.yield(i) end end) return f() + f() + f()")
            .eval()
            .unwrap();
        assert_eq!(sum, 6);
    }
}
