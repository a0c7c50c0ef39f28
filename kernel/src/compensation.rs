//! Dynamic error compensation (HMPL ch. 14): a compensated axis takes a value from a 1-D,
//! 2-D or 3-D table over the reference positions of one to three reference axes, and its
//! position output is reference + compensation (HMPL 14.1, fig. 5.1.1). The table's
//! values live in the user table (HMPL ch. 11); `EnableComp` copies them into room each
//! axis reserves at start-up, so the RT thread never allocates for them. Between the
//! points: linear (default) or natural cubic spline (1-D and 2-D, HMPL 14.8); outside the
//! table the nearest end point's value (HMPL 14.1). Table layout and the choices the
//! manual leaves open: docs/decisions.md, "Compensation".

use api::{AxisError, ErrorCode};
use schema::shared::USER_TABLE_LEN;

use super::Kernel;

/// Points one axis' table holds at most (45 x 45 in 2-D, 12 x 12 x 12 in 3-D); a larger
/// table is refused with 0x83II012C (docs/decisions.md, "Compensation").
pub const MAX_COMP_POINTS: usize = 2048;
/// HMPL 14.1: the default largest compensation, mm or deg (`HCV_ID_max_comp_lim`).
pub const DEFAULT_COMP_LIMIT: f64 = 1.0;
/// The largest number a table's setup may bring, as the coordinates of a path (HMPL 8.3);
/// the registry's range (`api::Quantity::CompTable`) is the compensated axis' counts.
const MAX_COMP_COORDINATE: f64 = 1e9;

/// HMPL 14.8: how the table is read between its points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Algorithm {
    /// 0: first-order linear (the default).
    #[default]
    Linear,
    /// 1: natural cubic spline (not for 3-D tables).
    Spline,
}

/// A table's geometry, as `SetupComp`, `SetupComp2D` and `SetupComp3D` give it: for each
/// of `dims` dimensions, the reference axis, the first point (`base`), the distance
/// between points and their number. The first dimension varies fastest in the user table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    pub(crate) dims: usize,
    /// Index of the first value in the user table.
    pub(crate) start: usize,
    pub(crate) base: [f64; 3],
    pub(crate) interval: [f64; 3],
    pub(crate) points: [usize; 3],
    pub(crate) ref_axes: [u8; 3],
}

impl Setup {
    /// Checks the arguments of a setup call (the compensated axis' and the reference axes'
    /// ids are checked by the kernel): 0x83II012C for what no table can be.
    pub fn new(
        start: i64,
        base: &[f64],
        interval: &[f64],
        points: &[f64],
        ref_axes: &[f64],
        dims: usize,
    ) -> Result<(Setup, [i64; 3]), AxisError> {
        let invalid = AxisError::CmdInvalidParameter;
        if [base.len(), interval.len(), points.len(), ref_axes.len()].iter().any(|&n| n < dims) {
            return Err(invalid);
        }
        let mut setup = Setup { dims, start: 0, base: [0.0; 3], interval: [1.0; 3], points: [1; 3], ref_axes: [0; 3] };
        let mut axes = [0i64; 3];
        for d in 0..dims {
            let (b, h, n, a) = (base[d], interval[d], points[d], ref_axes[d]);
            let whole = |v: f64| v.is_finite() && v.fract() == 0.0;
            if !(b.is_finite()
                && b.abs() <= MAX_COMP_COORDINATE
                && h.is_finite()
                && h > 0.0
                && h <= MAX_COMP_COORDINATE)
                || !(whole(n) && (2.0..=MAX_COMP_POINTS as f64).contains(&n))
                || !(whole(a) && a.abs() <= MAX_COMP_COORDINATE)
            {
                return Err(invalid);
            }
            (setup.base[d], setup.interval[d], setup.points[d]) = (b, h, n as usize);
            axes[d] = a as i64;
        }
        // The same reference axis twice would make two dimensions one.
        if (0..dims).any(|d| axes[..d].contains(&axes[d])) {
            return Err(invalid);
        }
        let len = setup.values();
        let start = usize::try_from(start).map_err(|_| invalid)?;
        if len > MAX_COMP_POINTS || start.checked_add(len).is_none_or(|end| end > USER_TABLE_LEN) {
            return Err(invalid);
        }
        setup.start = start;
        Ok((setup, axes))
    }

    /// The number of values in the table.
    pub fn values(&self) -> usize {
        self.points[..self.dims].iter().product()
    }

    /// Where `x` falls along dimension `d`: the cell's first point and the fraction into
    /// it; clamped to the table's ends (HMPL 14.1: the nearest end point's value).
    fn cell(&self, d: usize, x: f64) -> (usize, f64) {
        let last = self.points[d] - 1;
        let s = ((x - self.base[d]) / self.interval[d]).clamp(0.0, last as f64);
        let i = (s.floor() as usize).min(last - 1);
        (i, s - i as f64)
    }
}

/// Whether the table is in use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    Off,
    /// `EnableComp` was accepted: the values are copied before the kernel's next step.
    Loading,
    Active,
}

/// One axis' compensation: its setup, its values and the spline's second derivatives in
/// room reserved at start-up.
struct Table {
    setup: Option<Setup>,
    algorithm: Algorithm,
    phase: Phase,
    values: Vec<f64>,
    /// The natural spline's second derivatives along the first dimension (each row).
    moments: Vec<f64>,
    /// The largest compensation (HMPL 14.1).
    limit: f64,
    /// The last value was beyond the limit: the error is raised once per excursion.
    over_limit: bool,
    /// `EnableComp`'s answer, once the values are copied.
    result: Option<Result<(), AxisError>>,
}

impl Table {
    /// Copies the values from the user table (`user_table(i)`: entry `i`) and makes the
    /// table active; a value that is not a finite number refuses it (0x83II012C).
    fn load(&mut self, user_table: &impl Fn(usize) -> Option<f64>, sweep: &mut [f64]) {
        let Some(setup) = self.setup else { return };
        let len = setup.values();
        let mut finite = true;
        for (i, value) in self.values[..len].iter_mut().enumerate() {
            *value = user_table(setup.start + i).unwrap_or(f64::NAN);
            finite &= value.is_finite();
        }
        if !finite {
            self.phase = Phase::Off;
            self.result = Some(Err(AxisError::CmdInvalidParameter));
            return;
        }
        let moments = &mut self.moments[..len];
        moments.fill(0.0);
        if self.algorithm == Algorithm::Spline {
            let n0 = setup.points[0];
            for (row, m) in self.values[..len].chunks(n0).zip(moments.chunks_mut(n0)) {
                spline_moments(row, setup.interval[0], m, sweep);
            }
        }
        self.phase = Phase::Active;
        self.over_limit = false;
        self.result = Some(Ok(()));
    }

    /// The table's value at reference positions `at`. A 2-D spline is the tensor-product
    /// natural spline: each row's spline at `at[0]`, then the spline through those values
    /// at `at[1]`.
    fn value(&self, setup: &Setup, at: [f64; 3], scratch: &mut Scratch) -> f64 {
        match (self.algorithm, setup.dims) {
            (Algorithm::Spline, 1) => spline_at(&self.values[..setup.values()], &self.moments, setup, 0, at[0]),
            (Algorithm::Spline, _) => {
                let (n0, n1) = (setup.points[0], setup.points[1]);
                let Scratch { column, column_moments, sweep } = scratch;
                let rows = self.values[..n0 * n1].chunks(n0).zip(self.moments.chunks(n0));
                for (c, (row, m)) in column.iter_mut().zip(rows) {
                    *c = spline_at(row, m, setup, 0, at[0]);
                }
                spline_moments(&column[..n1], setup.interval[1], column_moments, sweep);
                spline_at(&column[..n1], column_moments, setup, 1, at[1])
            }
            (Algorithm::Linear, _) => multilinear(&self.values, setup, at),
        }
    }
}

/// The room a spline needs: a 2-D table's column of row values and its second
/// derivatives, and the factors of the tridiagonal solve.
struct Scratch {
    column: Vec<f64>,
    column_moments: Vec<f64>,
    sweep: Vec<f64>,
}

/// Every axis' compensation, and the room a spline needs.
pub(crate) struct Compensations {
    tables: Vec<Table>,
    scratch: Scratch,
}

impl Compensations {
    pub fn new(axes: usize) -> Self {
        let table = || Table {
            setup: None,
            algorithm: Algorithm::Linear,
            phase: Phase::Off,
            values: vec![0.0; MAX_COMP_POINTS],
            moments: vec![0.0; MAX_COMP_POINTS],
            limit: DEFAULT_COMP_LIMIT,
            over_limit: false,
            result: None,
        };
        // A 2-D table's column has at most half the points: each dimension has two or more.
        let column = MAX_COMP_POINTS / 2;
        Compensations {
            tables: (0..axes).map(|_| table()).collect(),
            scratch: Scratch {
                column: vec![0.0; column],
                column_moments: vec![0.0; column],
                sweep: vec![0.0; MAX_COMP_POINTS],
            },
        }
    }

    pub fn is_active(&self, axis: usize) -> bool {
        self.tables[axis].phase != Phase::Off
    }
}

impl Kernel {
    /// HMPL 14.4 to 14.6: a table's geometry (`setup`'s reference axes in `ref_axes`);
    /// refused while the compensation is active (0x83II00D2), for a reference axis that
    /// does not exist and for a spline on a 3-D table (0x83II012C).
    pub fn setup_comp(&mut self, axis: i64, setup: Result<(Setup, [i64; 3]), AxisError>) -> Result<(), ErrorCode> {
        let a = self.axis_id(axis)?;
        let (mut setup, ref_axes) = setup.map_err(|e| self.refuse(a, e))?;
        for (slot, &id) in setup.ref_axes.iter_mut().zip(&ref_axes).take(setup.dims) {
            *slot = self.axis_id(id).map_err(|_| self.refuse(a, AxisError::CmdInvalidParameter))?;
        }
        let table = &self.compensation.tables[a as usize];
        if table.phase != Phase::Off {
            return Err(self.refuse(a, AxisError::CmdInvalidCompEnabled));
        }
        if setup.dims == 3 && table.algorithm == Algorithm::Spline {
            return Err(self.refuse(a, AxisError::CmdInvalidParameter));
        }
        self.compensation.tables[a as usize].setup = Some(setup);
        Ok(())
    }

    /// HMPL 14.8: 0 linear, 1 cubic spline (not on a 3-D table); not while active.
    pub fn set_comp_alg_type(&mut self, axis: i64, alg_type: i64) -> Result<(), ErrorCode> {
        let a = self.axis_id(axis)?;
        let table = &self.compensation.tables[a as usize];
        let algorithm = match alg_type {
            0 => Algorithm::Linear,
            1 if table.setup.is_none_or(|s| s.dims < 3) => Algorithm::Spline,
            _ => return Err(self.refuse(a, AxisError::CmdInvalidParameter)),
        };
        if table.phase != Phase::Off {
            return Err(self.refuse(a, AxisError::CmdInvalidCompEnabled));
        }
        self.compensation.tables[a as usize].algorithm = algorithm;
        Ok(())
    }

    /// HMPL 14.2: only while the axis is disabled (0x83II006E), after a setup (0x83II0190),
    /// with the compensated and the reference axes homed (0x83II0064, HMPL 14.1). The values
    /// are copied before the kernel's next step (`load_compensation`), which answers.
    pub fn enable_comp(&mut self, axis: i64) -> Result<(), ErrorCode> {
        let a = self.axis_id(axis)?;
        if !self.axes[a as usize].is_disabled() {
            return Err(self.refuse(a, AxisError::CmdInvalidEnabled));
        }
        let Some(setup) = self.compensation.tables[a as usize].setup else {
            return Err(self.refuse(a, AxisError::CompNotCnfg));
        };
        let mut axes = std::iter::once(a).chain(setup.ref_axes[..setup.dims].iter().copied());
        if !axes.all(|id| self.axes[id as usize].home_state().is_homed()) {
            return Err(self.refuse(a, AxisError::CmdInvalidState));
        }
        let table = &mut self.compensation.tables[a as usize];
        table.phase = Phase::Loading;
        table.result = None;
        Ok(())
    }

    /// `EnableComp`'s answer for `axis`, once, when its values are copied.
    pub fn take_comp_result(&mut self, axis: i64) -> Option<Result<(), ErrorCode>> {
        let a = self.axis_id(axis).ok()?;
        let result = self.compensation.tables[a as usize].result.take()?;
        Some(result.map_err(|e| ErrorCode::axis(a, e)))
    }

    /// HMPL 14.3: only while disabled (0x83II006E); the setup is cleared, and the reference
    /// is the position where the axis stands, now without compensation.
    pub fn disable_comp(&mut self, axis: i64) -> Result<(), ErrorCode> {
        let a = self.axis_id(axis)?;
        if !self.axes[a as usize].is_disabled() {
            return Err(self.refuse(a, AxisError::CmdInvalidEnabled));
        }
        let table = &mut self.compensation.tables[a as usize];
        table.setup = None;
        table.phase = Phase::Off;
        table.over_limit = false;
        self.axes[a as usize].end_compensation();
        Ok(())
    }

    /// IsCompActive (HMPL 5.4.14): axis `axis` has a table enabled (EnableComp).
    pub fn is_comp_active(&self, axis: usize) -> bool {
        self.compensation.is_active(axis)
    }

    /// HMPL 14.1: the axis' coordinates stay fixed while it is compensated, so what moves
    /// its origin (`SetPos`, `MoveHome`) is refused with 0x83II00D2.
    pub fn keep_coordinates(&mut self, axis: i64) -> Result<(), ErrorCode> {
        let a = self.axis_id(axis)?;
        if self.compensation.is_active(a as usize) {
            return Err(self.refuse(a, AxisError::CmdInvalidCompEnabled));
        }
        Ok(())
    }

    /// Copies the tables `EnableComp` asked for from the user table (`user_table(i)`: entry
    /// `i`) and makes them active; a value that is not a finite number refuses the table
    /// (0x83II012C). Before the kernel's step, in the cycle of the command.
    pub fn load_compensation(&mut self, user_table: impl Fn(usize) -> Option<f64>) {
        let Compensations { tables, scratch } = &mut self.compensation;
        for table in tables.iter_mut().filter(|t| t.phase == Phase::Loading) {
            table.load(&user_table, &mut scratch.sweep);
        }
    }

    /// Each cycle, once every reference is known: each active table's value at its
    /// reference axes' reference positions becomes its axis' compensation, clamped to the
    /// limit; passing the limit stops the axis in ErrorStop with 0x83II0802 (HMPL 14.1).
    pub(super) fn compensate(&mut self) {
        for a in 0..self.axes.len() {
            let table = &self.compensation.tables[a];
            let (Phase::Active, Some(setup)) = (table.phase, table.setup) else { continue };
            let at = setup.ref_axes.map(|r| self.axes.get(r as usize).map_or(0.0, |axis| axis.reference().pos));
            let Compensations { tables, scratch } = &mut self.compensation;
            let table = &mut tables[a];
            let value = table.value(&setup, at, scratch);
            let over = value.abs() > table.limit;
            let newly_over = over && !table.over_limit;
            table.over_limit = over;
            let axis = &mut self.axes[a];
            axis.set_compensation(value.clamp(-table.limit, table.limit));
            if newly_over {
                axis.compensation_limit();
            }
        }
    }
}

/// The value of a table at `at`, linear between the points of every dimension.
fn multilinear(values: &[f64], setup: &Setup, at: [f64; 3]) -> f64 {
    let mut cells = [(0, 0.0); 3];
    for (d, cell) in cells.iter_mut().enumerate().take(setup.dims) {
        *cell = setup.cell(d, at[d]);
    }
    (0..1usize << setup.dims)
        .map(|corner| {
            let (mut weight, mut index, mut stride) = (1.0, 0, 1);
            for (d, &(i, t)) in cells.iter().enumerate().take(setup.dims) {
                let upper = corner >> d & 1;
                weight *= if upper == 1 { t } else { 1.0 - t };
                index += (i + upper) * stride;
                stride *= setup.points[d];
            }
            weight * values[index]
        })
        .sum()
}

/// The natural cubic spline through `y` (points `h` apart): its second derivatives in
/// `m`, zero at both ends, from the tridiagonal system
/// `m[i-1] + 4 m[i] + m[i+1] = 6 (y[i+1] - 2 y[i] + y[i-1]) / h²` (Thomas' algorithm;
/// `sweep` holds its factors).
fn spline_moments(y: &[f64], h: f64, m: &mut [f64], sweep: &mut [f64]) {
    let n = y.len();
    m[..n].fill(0.0);
    let k = 6.0 / (h * h);
    let (mut c, mut d) = (0.0, 0.0);
    for i in 1..n.saturating_sub(1) {
        let pivot = 4.0 - c;
        c = 1.0 / pivot;
        d = (k * (y[i + 1] - 2.0 * y[i] + y[i - 1]) - d) / pivot;
        sweep[i] = c;
        m[i] = d;
    }
    for i in (1..n.saturating_sub(2)).rev() {
        m[i] -= sweep[i] * m[i + 1];
    }
}

/// The spline through `y` with second derivatives `m` along dimension `d` at `x`.
fn spline_at(y: &[f64], m: &[f64], setup: &Setup, d: usize, x: f64) -> f64 {
    let (i, t) = setup.cell(d, x);
    let h = setup.interval[d];
    let u = 1.0 - t;
    u * y[i] + t * y[i + 1] + h * h / 6.0 * ((u * u * u - u) * m[i] + (t * t * t - t) * m[i + 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(dims: usize, base: &[f64], interval: &[f64], points: &[f64]) -> Setup {
        Setup::new(1, base, interval, points, &[0.0, 1.0, 2.0], dims).unwrap().0
    }

    /// HMPL 14.1.1 example 1: -100..700 every 200 mm.
    const EXAMPLE_1: [f64; 5] = [-0.2, 0.1, -0.3, 0.4, -0.1];

    #[test]
    fn linear_1d_at_points_between_and_outside() {
        let s = setup(1, &[-100.0], &[200.0], &[5.0]);
        let at = |x| multilinear(&EXAMPLE_1, &s, [x, 0.0, 0.0]);
        assert_eq!(at(100.0), 0.1);
        assert!((at(0.0) - -0.05).abs() < 1e-12);
        assert!((at(550.0) - (0.4 + 0.25 * -0.5)).abs() < 1e-12);
        assert_eq!(at(-1000.0), -0.2);
        assert_eq!(at(5000.0), -0.1);
    }

    #[test]
    fn the_natural_spline_passes_its_points_and_has_zero_curvature_at_the_ends() {
        let s = setup(1, &[-100.0], &[200.0], &[5.0]);
        let (mut m, mut sweep) = ([0.0; 5], [0.0; 5]);
        spline_moments(&EXAMPLE_1, 200.0, &mut m, &mut sweep);
        for (k, &y) in EXAMPLE_1.iter().enumerate() {
            assert!((spline_at(&EXAMPLE_1, &m, &s, 0, -100.0 + 200.0 * k as f64) - y).abs() < 1e-12);
        }
        assert_eq!((m[0], m[4]), (0.0, 0.0));
        // The system's rows hold: m[i-1] + 4 m[i] + m[i+1] = 6 (y[i+1] - 2 y[i] + y[i-1]) / h².
        for i in 1..4 {
            let rhs = 6.0 * (EXAMPLE_1[i + 1] - 2.0 * EXAMPLE_1[i] + EXAMPLE_1[i - 1]) / 200.0_f64.powi(2);
            assert!((m[i - 1] + 4.0 * m[i] + m[i + 1] - rhs).abs() < 1e-15);
        }
    }

    /// A 2-D spline over rows that are example 1's data shifted by a constant per row: the
    /// tensor-product spline is the 1-D spline plus the spline through the shifts.
    #[test]
    fn the_2d_spline_is_the_1d_spline_along_each_dimension() {
        let mut c = Compensations::new(1);
        let shifts = [0.0, 0.1, -0.1];
        let data: Vec<f64> = shifts.iter().flat_map(|s| EXAMPLE_1.map(|y| y + s)).collect();
        let table = &mut c.tables[0];
        let s = setup(2, &[-100.0, 0.0], &[200.0, 50.0], &[5.0, 3.0]);
        (table.setup, table.algorithm) = (Some(s), Algorithm::Spline);
        table.load(&|i| data.get(i - 1).copied(), &mut c.scratch.sweep);
        assert_eq!(table.result, Some(Ok(())));
        // Along y, the natural spline through 0, 0.1, -0.1 (h = 50): M1 = 6 (-0.1 - 0.2) /
        // 50² / 4, at y = 25 (t = 1/2): 0.05 + 50²/6 (-3/8) M1 = 0.05 + 0.028125.
        let along_y = 0.05 + 2500.0 / 6.0 * -0.375 * (6.0 * -0.3 / 2500.0 / 4.0);
        let v = table.value(&s, [0.0, 25.0, 0.0], &mut c.scratch);
        assert!((v - (0.0578125 + along_y)).abs() < 1e-12, "{v}");
        // At a point of the table, its value.
        assert!((table.value(&s, [300.0, 100.0, 0.0], &mut c.scratch) - (-0.3 - 0.1)).abs() < 1e-12);
    }

    #[test]
    fn setups_no_table_can_be_are_refused() {
        let bad = |start, base: &[f64], interval: &[f64], points: &[f64], axes: &[f64], dims| {
            Setup::new(start, base, interval, points, axes, dims).unwrap_err()
        };
        let e = AxisError::CmdInvalidParameter;
        assert_eq!(bad(0, &[0.0], &[0.0], &[5.0], &[0.0], 1), e);
        assert_eq!(bad(0, &[f64::NAN], &[1.0], &[5.0], &[0.0], 1), e);
        assert_eq!(bad(0, &[0.0], &[1.0], &[1.0], &[0.0], 1), e);
        assert_eq!(bad(0, &[0.0], &[1.0], &[2.5], &[0.0], 1), e);
        assert_eq!(bad(-1, &[0.0], &[1.0], &[5.0], &[0.0], 1), e);
        assert_eq!(bad(511_998, &[0.0], &[1.0], &[5.0], &[0.0], 1), e);
        assert_eq!(bad(0, &[0.0, 0.0], &[1.0, 1.0], &[50.0, 50.0], &[0.0, 1.0], 2), e);
        assert_eq!(bad(0, &[0.0, 0.0], &[1.0, 1.0], &[3.0, 3.0], &[1.0, 1.0], 2), e);
        assert_eq!(bad(0, &[0.0], &[1.0], &[3.0], &[0.0], 2), e);
        assert!(Setup::new(0, &[0.0, 0.0], &[1.0, 1.0], &[45.0, 45.0], &[0.0, 1.0], 2).is_ok());
    }
}
