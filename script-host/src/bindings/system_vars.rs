//! The variables every program sees (`api::system_vars`): `system_fclk` and
//! `system_timeInMs` from the newest snapshot; the test variables, the user table and
//! `system_mtest` in the shared data; `_TASKID_`; and `task_vars`, the task's variables
//! that survive its restarts. Scalars are resolved by the globals' metatable, tables are
//! proxies whose every read and write goes to shared memory.

use std::rc::Rc;

use api::system_vars::SystemVar;
use mlua::{Lua, MetaMethod, UserData, UserDataMethods, Value};
use schema::shared::{TestValue, TestVar, USER_TABLE_LEN, VarValue};

use api::{CommandCall, QueryCall};
use calls::query;

use super::{Host, error_here, round_trip, type_name};

/// `_TASKID_`, a plain global.
pub fn set_task_id(lua: &Lua, task: u8) -> mlua::Result<()> {
    lua.globals().raw_set("_TASKID_", task as i64)
}

/// Installs the variables but `_TASKID_` (`set_task_id`, once the task is known).
pub fn install_system_variables(lua: &Lua, host: Rc<Host>) -> mlua::Result<()> {
    let globals = lua.globals();
    globals.raw_set("system_user_table", SharedArray { host: host.clone(), kind: ArrayKind::UserTable })?;
    globals.raw_set("system_mtest", SharedArray { host: host.clone(), kind: ArrayKind::MTest })?;
    globals.raw_set("task_vars", TaskVariables { host: host.clone() })?;
    globals.raw_set("HIMC_GPI", Pins { host: host.clone(), outputs: false })?;
    globals.raw_set("HIMC_GPO", Pins { host: host.clone(), outputs: true })?;

    let meta = lua.create_table()?;
    let reader = host.clone();
    meta.set(
        "__index",
        lua.create_function(move |_, (_, name): (Value, Value)| {
            // A global the program has not set, or a system variable: time and the test
            // variables change without a query, so a `Till` condition reading one is not
            // watched.
            reader.spoil_watch();
            let Value::String(name) = name else { return Ok(Value::Nil) };
            let Some(var) = SystemVar::parse(&name.to_str()?) else { return Ok(Value::Nil) };
            Ok(match var {
                SystemVar::Fclk => Value::Integer(reader.endpoint.borrow_mut().snapshot().cycle as i64),
                SystemVar::TimeInMs => Value::Integer(reader.endpoint.borrow_mut().snapshot().time_in_ms as i64),
                SystemVar::LTest(i) => test_value(&reader, TestVar::L(i)),
                SystemVar::DTest(i) => test_value(&reader, TestVar::D(i)),
                SystemVar::UserTable
                | SystemVar::MTest
                | SystemVar::TaskId
                | SystemVar::TaskVars
                | SystemVar::HimcGpi
                | SystemVar::HimcGpo => Value::Nil,
            })
        })?,
    )?;
    meta.set(
        "__newindex",
        lua.create_function(move |lua, (globals, name, value): (mlua::Table, Value, Value)| {
            let var = match &name {
                Value::String(s) => SystemVar::parse(&s.to_str()?),
                _ => None,
            };
            let test_var = match var {
                None => return globals.raw_set(name, value),
                Some(SystemVar::LTest(i)) => TestVar::L(i),
                Some(SystemVar::DTest(i)) => TestVar::D(i),
                Some(_) => return Err(error_here(lua, format!("{} is read-only", name.to_string()?))),
            };
            let number = number(lua, &value, &name.to_string()?)?;
            host.shared.set_test_var(test_var, number);
            Ok(())
        })?,
    )?;
    globals.set_metatable(Some(meta))
}

fn test_value(host: &Host, var: TestVar) -> Value {
    match host.shared.test_var(var) {
        Some(TestValue::Int(i)) => Value::Integer(i),
        Some(TestValue::Double(d)) => Value::Number(d),
        None => Value::Nil,
    }
}

fn number(lua: &Lua, value: &Value, what: &str) -> mlua::Result<f64> {
    match value {
        Value::Integer(i) => Ok(*i as f64),
        Value::Number(n) => Ok(*n),
        Value::Boolean(b) => Ok(*b as i64 as f64),
        other => Err(error_here(lua, format!("{what} holds numbers, not {}", type_name(other)))),
    }
}

#[derive(Clone, Copy)]
enum ArrayKind {
    UserTable,
    MTest,
}

/// `system_user_table[i]` and `system_mtest[i]`, indices from 0 as in HMPL.
struct SharedArray {
    host: Rc<Host>,
    kind: ArrayKind,
}

impl SharedArray {
    fn name(&self) -> &'static str {
        match self.kind {
            ArrayKind::UserTable => "system_user_table",
            ArrayKind::MTest => "system_mtest",
        }
    }

    fn len(&self) -> usize {
        match self.kind {
            ArrayKind::UserTable => USER_TABLE_LEN,
            ArrayKind::MTest => api::system_vars::TEST_VARS,
        }
    }

    fn index(&self, lua: &Lua, key: &Value) -> mlua::Result<usize> {
        let i = match key {
            Value::Integer(i) => *i,
            Value::Number(n) if n.fract() == 0.0 => *n as i64,
            other => {
                return Err(error_here(
                    lua,
                    format!("{} takes integer indices, not {}", self.name(), type_name(other)),
                ));
            }
        };
        usize::try_from(i)
            .ok()
            .filter(|&i| i < self.len())
            .ok_or_else(|| error_here(lua, format!("{}[{i}]: indices are 0..{} (0x138F)", self.name(), self.len() - 1)))
    }
}

impl UserData for SharedArray {
    fn add_methods<M: UserDataMethods<Self>>(methods: &mut M) {
        methods.add_meta_method(MetaMethod::Index, |lua, this, key: Value| {
            this.host.beat();
            let i = this.index(lua, &key)?;
            let value = match this.kind {
                ArrayKind::UserTable => this.host.shared.user_table(i),
                ArrayKind::MTest => match this.host.shared.test_var(TestVar::M(i)) {
                    Some(TestValue::Double(d)) => Some(d),
                    _ => None,
                },
            };
            Ok(value.unwrap_or(0.0))
        });
        methods.add_meta_method(MetaMethod::NewIndex, |lua, this, (key, value): (Value, Value)| {
            this.host.beat();
            let i = this.index(lua, &key)?;
            let v = number(lua, &value, this.name())?;
            match this.kind {
                ArrayKind::UserTable => this.host.shared.set_user_table(i, v),
                ArrayKind::MTest => this.host.shared.set_test_var(TestVar::M(i), v),
            };
            Ok(())
        });
        methods.add_meta_method(MetaMethod::Len, |_, this, ()| Ok(this.len()));
    }
}

/// `task_vars.name`: kept in shared memory, so they outlive the task's process.
struct TaskVariables {
    host: Rc<Host>,
}

impl UserData for TaskVariables {
    fn add_methods<M: UserDataMethods<Self>>(methods: &mut M) {
        methods.add_meta_method(MetaMethod::Index, |lua, this, name: String| {
            this.host.beat();
            Ok(match this.host.shared.task_vars(this.host.task()).get(&name) {
                None => Value::Nil,
                Some(VarValue::Int(i)) => Value::Integer(i),
                Some(VarValue::Double(d)) => Value::Number(d),
                Some(VarValue::Bool(b)) => Value::Boolean(b),
                Some(VarValue::Text(t)) => Value::String(lua.create_string(&t)?),
            })
        });
        methods.add_meta_method(MetaMethod::NewIndex, |lua, this, (name, value): (String, Value)| {
            this.host.beat();
            let value = match value {
                Value::Nil => None,
                Value::Integer(i) => Some(VarValue::Int(i)),
                Value::Number(n) => Some(VarValue::Double(n)),
                Value::Boolean(b) => Some(VarValue::Bool(b)),
                Value::String(s) => Some(VarValue::Text(s.to_str()?.to_string())),
                other => {
                    return Err(error_here(
                        lua,
                        format!("task_vars.{name}: holds numbers, booleans and strings, not {}", type_name(&other)),
                    ));
                }
            };
            this.host
                .shared
                .task_vars(this.host.task())
                .set(&name, value.as_ref())
                .map_err(|e| error_here(lua, format!("task_vars.{name}: {e}")))
        });
    }
}

/// HMPL 19.4, 19.5: `HIMC_GPI` and `HIMC_GPO`, the controller's pins as an expression. In C
/// they are macros usable as a value and (outputs) as an lvalue; in Lua they are tables
/// indexed by the pin (1..8) and callable, so `if HIMC_GPI[4] and HIMC_GPI(6) then` reads
/// as the manual's `if (HIMC_GPI(4) && HIMC_GPI(6))`. A pin reads as a boolean: Lua's 0 is true.
struct Pins {
    host: Rc<Host>,
    outputs: bool,
}

impl Pins {
    fn name(&self) -> &'static str {
        if self.outputs { "HIMC_GPO" } else { "HIMC_GPI" }
    }

    fn pin(&self, lua: &Lua, key: &Value) -> mlua::Result<i64> {
        match key {
            Value::Integer(i) => Ok(*i),
            Value::Number(n) if n.fract() == 0.0 && n.abs() < 1e15 => Ok(*n as i64),
            other => Err(error_here(lua, format!("{} takes pins 1..8, not {}", self.name(), type_name(other)))),
        }
    }

    fn get(&self, lua: &Lua, key: &Value) -> mlua::Result<bool> {
        self.host.beat();
        let pin = self.pin(lua, key)?;
        let call = if self.outputs { QueryCall::GetGPO { gpo_idx: pin } } else { QueryCall::GetGPI { gpi_idx: pin } };
        let answer = query::evaluate(&call, self.host.endpoint.borrow_mut().snapshot());
        match answer.map(|a| a.0) {
            Ok(query::Value::Int(1)) => Ok(true),
            Ok(query::Value::Int(0)) => Ok(false),
            _ => Err(error_here(lua, format!("{}[{pin}]: the pins are 1..8 (0x138F)", self.name()))),
        }
    }
}

impl UserData for Pins {
    fn add_methods<M: UserDataMethods<Self>>(methods: &mut M) {
        methods.add_meta_method(MetaMethod::Index, |lua, this, key: Value| this.get(lua, &key));
        methods.add_meta_method(MetaMethod::Call, |lua, this, key: Value| this.get(lua, &key));
        methods.add_meta_method(MetaMethod::NewIndex, |lua, this, (key, value): (Value, Value)| {
            if !this.outputs {
                return Err(error_here(lua, "HIMC_GPI is read-only: inputs are set by what is wired to them"));
            }
            this.host.beat();
            let gpo_idx = this.pin(lua, &key)?;
            let on = match value {
                Value::Boolean(b) => b,
                Value::Integer(i) => i != 0,
                Value::Number(n) => n != 0.0,
                other => {
                    return Err(error_here(
                        lua,
                        format!("HIMC_GPO[{gpo_idx}] takes true, false or a number, not {}", type_name(&other)),
                    ));
                }
            };
            let reply = round_trip(lua, &this.host, &CommandCall::SetGPO { gpo_idx, on_off: on as i64 })?;
            if reply.values[0] != 0 {
                return Err(error_here(lua, format!("HIMC_GPO[{gpo_idx}]: the pins are 1..8 (0x138F)")));
            }
            Ok(())
        });
    }
}
