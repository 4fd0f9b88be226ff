//! Boxes and rods: arrays in, a checked rod system out, and out again in
//! the frame they came in.

use std::sync::Arc;

use numpy::ndarray::{Array1, Array2, ArrayView1, ArrayView2};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use rgc::Error;
use rgc::error::short;
use rgc::rods::ensemble::{Dist, Ensemble, Orientation};
use rgc::rods::{Cut, Domain, MAX_RODS, Periodic, Rod, RodSystem, wrap};
use rgc::usage::reserve;

use crate::{error, interrupt, repr, value_error};

/// Peak bytes per rod of building a system (rods, the checked copy, the
/// index that finds rods given twice): 303 measured for 2 million rods,
/// with room to spare. Checked before anything is allocated.
const BUILD_BYTES_PER_ROD: u64 = 400;

/// A box `[0, L_x) x [0, L_y) x [0, L_z)` and its periodic axes, or, as
/// `centred` (HOOMD's and freud's convention), `[-L/2, L/2)`: points go in
/// and come out in the box's own frame.
#[pyclass(name = "Box", module = "rgc", frozen)]
#[derive(Clone)]
pub struct PyBox {
    pub domain: Domain,
    pub centred: bool,
}

fn periodic(name: &str) -> PyResult<Periodic> {
    match name {
        "xyz" => Ok(Periodic::Xyz),
        "xy" => Ok(Periodic::Xy),
        "none" => Ok(Periodic::None),
        _ => Err(value_error(format!(
            "periodic must be 'xyz', 'xy' or 'none', got {name:?}"
        ))),
    }
}

/// Three sides from one number, one sequence of three, or three numbers
/// (freud's `Box(Lx, Ly, Lz)`).
fn sides(args: &Bound<'_, PyTuple>) -> PyResult<[f64; 3]> {
    let bad = |got: String| {
        value_error(format!(
            "box sides must be a number or three numbers, got {got} (periodic and centred are keywords: Box(5.0, periodic='xy'))"
        ))
    };
    let values: Vec<f64> = match args.len() {
        1 => {
            let a = args.get_item(0)?;
            if let Ok(l) = a.extract::<f64>() {
                return Ok([l; 3]);
            }
            if a.is_instance_of::<pyo3::types::PyString>() {
                return Err(bad(repr(&a)));
            }
            a.extract().map_err(|_| bad(repr(&a)))?
        }
        _ => args
            .iter()
            .map(|a| a.extract::<f64>().map_err(|_| bad(repr(&a))))
            .collect::<PyResult<_>>()?,
    };
    <[f64; 3]>::try_from(values.as_slice()).map_err(|_| bad(values.len().to_string()))
}

#[pymethods]
impl PyBox {
    /// `Box(L)`, `Box([Lx, Ly, Lz])` or `Box(Lx, Ly, Lz)`; `periodic`
    /// 'xyz', 'xy' (walls in z) or 'none'; `centred` for `[-L/2, L/2)`.
    #[new]
    #[pyo3(signature = (*sides, periodic="xyz", centred=false))]
    fn new(sides: &Bound<'_, PyTuple>, periodic: &str, centred: bool) -> PyResult<Self> {
        let domain = Domain::new(self::sides(sides)?, self::periodic(periodic)?).map_err(error)?;
        Ok(PyBox { domain, centred })
    }

    /// Side lengths, shape (3,).
    #[getter]
    fn sides<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.domain.sides.to_vec().into_pyarray(py)
    }

    /// 'xyz', 'xy' or 'none'.
    #[getter]
    fn periodic(&self) -> &'static str {
        self.domain.periodic.name()
    }

    #[getter]
    fn centred(&self) -> bool {
        self.centred
    }

    #[getter]
    fn volume(&self) -> f64 {
        self.domain.volume()
    }

    /// Points of shape (N, 3) wrapped into the box along its periodic axes,
    /// in the box's own frame (`[-L/2, L/2)` if centred, else `[0, L)`).
    fn wrap<'py>(
        &self,
        py: Python<'py>,
        points: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let p = points.as_array();
        check_points(&p, "points")?;
        let mut out = p.to_owned();
        for mut row in out.rows_mut() {
            let inside = self.to_rgc([row[0], row[1], row[2]]);
            let back = self.to_frame(inside);
            row.iter_mut().zip(back).for_each(|(x, b)| *x = b);
        }
        Ok(out.into_pyarray(py))
    }

    /// What `pickle` rebuilds the box from.
    fn __getnewargs_ex__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyTuple>, Bound<'py, PyDict>)> {
        let kwargs = PyDict::new(py);
        kwargs.set_item("periodic", self.domain.periodic.name())?;
        kwargs.set_item("centred", self.centred)?;
        Ok((PyTuple::new(py, self.domain.sides)?, kwargs))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyBox>()
            .is_ok_and(|o| o.get().domain == self.domain && o.get().centred == self.centred)
    }

    fn __repr__(&self) -> String {
        let [x, y, z] = self.domain.sides.map(short);
        format!(
            "Box(sides=({x}, {y}, {z}), periodic={:?}, centred={})",
            self.domain.periodic.name(),
            if self.centred { "True" } else { "False" }
        )
    }
}

impl PyBox {
    /// The lowest corner in the box's own frame: `-L/2` if centred, else 0.
    pub fn origin(&self) -> [f64; 3] {
        let half = if self.centred { -0.5 } else { 0.0 };
        self.domain.sides.map(|l| half * l)
    }

    /// A point of the box's frame in rgc's `[0, L)`, wrapped along periodic axes.
    fn to_rgc(&self, p: [f64; 3]) -> [f64; 3] {
        let o = self.origin();
        std::array::from_fn(|k| {
            let x = p[k] - o[k];
            if self.domain.wraps(k) {
                wrap(x, self.domain.sides[k])
            } else {
                x
            }
        })
    }

    /// A point of rgc's frame back in the box's own.
    pub fn to_frame(&self, p: [f64; 3]) -> [f64; 3] {
        let o = self.origin();
        std::array::from_fn(|k| p[k] + o[k])
    }
}

/// An (N, 3) array of finite numbers, or an error naming it (a NaN would
/// otherwise wrap silently into the box).
fn check_points(a: &ArrayView2<'_, f64>, what: &str) -> PyResult<()> {
    if a.ncols() != 3 {
        return Err(value_error(format!(
            "{what} must have shape (N, 3), got {:?}",
            a.shape()
        )));
    }
    match a
        .rows()
        .into_iter()
        .position(|r| r.iter().any(|x| !x.is_finite()))
    {
        Some(i) => Err(value_error(format!("{what} row {i} is not finite"))),
        None => Ok(()),
    }
}

/// Per-rod values: one number for all, or an (N,) array.
enum PerRod<'a> {
    All(f64),
    Each(ArrayView1<'a, f64>),
}

impl PerRod<'_> {
    fn get(&self, i: usize) -> f64 {
        match self {
            PerRod::All(x) => *x,
            PerRod::Each(a) => a[i],
        }
    }
}

/// A number, or the view of an (N,) array checked against the rods.
fn per_rod<'a>(
    number: Option<f64>,
    array: &'a Option<PyReadonlyArray1<'_, f64>>,
    n: usize,
    what: &str,
) -> PyResult<PerRod<'a>> {
    match (number, array) {
        (Some(x), _) => Ok(PerRod::All(x)),
        (None, Some(a)) if a.as_array().len() == n => Ok(PerRod::Each(a.as_array())),
        (None, Some(a)) => Err(value_error(format!(
            "{what} has {} values for {n} rods",
            a.as_array().len()
        ))),
        (None, None) => Err(value_error(format!("{what} are needed"))),
    }
}

/// Refuses, before any allocation, a system of `n` rods too large to
/// build: over the library's cap or over the memory this process has.
pub(crate) fn check_build(n: usize) -> PyResult<()> {
    if n >= MAX_RODS {
        return Err(error(Error::Memory(format!(
            "{n} rods, more than the {MAX_RODS} that fit in memory"
        ))));
    }
    let need = n as u64 * BUILD_BYTES_PER_ROD;
    match reserve(need, 0, None) {
        Err(refusal) => Err(error(Error::Memory(
            refusal.describe(&format!("building {n} rods")),
        ))),
        Ok(_) => Ok(()),
    }
}

/// A checked rod system in a box, kept in rgc's frame and shown in the
/// frame of the box it was given in.
#[pyclass(name = "Rods", module = "rgc", frozen)]
#[derive(Clone)]
pub struct PyRods {
    pub system: Arc<RodSystem>,
    /// Rods whose cores were cut at a wall.
    pub cut: usize,
    /// Whether the box it was given in is centred.
    pub centred: bool,
}

#[pymethods]
impl PyRods {
    /// Rods from float64 arrays (`rgc.Rods.from_arrays` converts and checks
    /// shapes first): `centres` (N, 3) in the box's frame, wrapped along
    /// periodic axes; `directions` (N, 3) or `quaternions` (N, 4); lengths
    /// and radii each a number or an (N,) array. Cores crossing a wall are
    /// cut to the box, as reading a file does.
    #[staticmethod]
    #[pyo3(signature = (r#box, centres, directions, quaternions, length, lengths, radius, radii, axis))]
    #[allow(clippy::too_many_arguments)]
    fn _from_arrays(
        py: Python<'_>,
        r#box: &PyBox,
        centres: PyReadonlyArray2<'_, f64>,
        directions: Option<PyReadonlyArray2<'_, f64>>,
        quaternions: Option<PyReadonlyArray2<'_, f64>>,
        length: Option<f64>,
        lengths: Option<PyReadonlyArray1<'_, f64>>,
        radius: Option<f64>,
        radii: Option<PyReadonlyArray1<'_, f64>>,
        axis: (f64, f64, f64),
    ) -> PyResult<Self> {
        let centres = centres.as_array();
        check_points(&centres, "centres")?;
        let n = centres.nrows();
        let directions = directions.as_ref().map(|d| d.as_array());
        let quaternions = quaternions.as_ref().map(|q| q.as_array());
        match (&directions, &quaternions) {
            (Some(d), None) => check_points(d, "directions")?,
            (None, Some(q)) if q.ncols() != 4 => {
                return Err(value_error(format!(
                    "quaternions must have shape (N, 4), got {:?}",
                    q.shape()
                )));
            }
            (None, Some(_)) => {}
            _ => return Err(value_error("give either directions or quaternions")),
        }
        let given = directions
            .as_ref()
            .or(quaternions.as_ref())
            .map_or(n, |a| a.nrows());
        if given != n {
            let what = if directions.is_some() {
                "directions"
            } else {
                "quaternions"
            };
            return Err(value_error(format!("{given} {what} for {n} centres")));
        }
        let lengths = per_rod(length, &lengths, n, "lengths")?;
        let radii = per_rod(radius, &radii, n, "radii")?;
        check_build(n)?;
        let body = [axis.0, axis.1, axis.2];
        let mut rods = Vec::with_capacity(n);
        let mut cut = 0;
        for i in 0..n {
            let axis = match (&directions, &quaternions) {
                (Some(d), _) => nalgebra::Vector3::new(d[[i, 0]], d[[i, 1]], d[[i, 2]]),
                (_, Some(q)) => {
                    rgc::rods::rotate([q[[i, 0]], q[[i, 1]], q[[i, 2]], q[[i, 3]]], body)
                        .ok_or_else(|| value_error(format!("quaternion {i} is not a rotation")))?
                }
                (None, None) => unreachable!("checked above"),
            };
            let c = r#box.to_rgc([centres[[i, 0]], centres[[i, 1]], centres[[i, 2]]]);
            let rod = Rod {
                center: c.into(),
                axis,
                length: lengths.get(i),
                radius: radii.get(i),
            };
            if let Some(why) = rod.defect() {
                return Err(value_error(format!("rod {i}: {why}")));
            }
            let rod = Rod::new(rod.center, rod.axis, rod.length, rod.radius);
            rods.push(match r#box.domain.cut(&rod) {
                Cut::Cut(c) => {
                    cut += 1;
                    c
                }
                Cut::Whole(_) | Cut::Outside => rod,
            });
        }
        let domain = r#box.domain;
        let system = py.detach(|| RodSystem::new(domain, rods)).map_err(error)?;
        Ok(PyRods::new(system, cut, r#box.centred))
    }

    fn __len__(&self) -> usize {
        self.system.len()
    }

    /// The box, centred if the rods were given in a centred one.
    #[getter(r#box)]
    fn get_box(&self) -> PyBox {
        self.r#box()
    }

    /// Centres in the box's frame (`[-L/2, L/2)` along periodic axes if
    /// centred, else `[0, L)`), shape (N, 3).
    #[getter]
    fn centres<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let b = self.r#box();
        self.column3(|r| b.to_frame(r.center.into()))
            .into_pyarray(py)
    }

    /// Unit directions, shape (N, 3).
    #[getter]
    fn directions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.column3(|r| r.axis.into()).into_pyarray(py)
    }

    /// Core lengths, shape (N,).
    #[getter]
    fn lengths<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        Array1::from_iter(self.system.rods.iter().map(|r| r.length)).into_pyarray(py)
    }

    /// Radii, shape (N,).
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        Array1::from_iter(self.system.rods.iter().map(|r| r.radius)).into_pyarray(py)
    }

    /// Rods whose cores were cut at a wall.
    #[getter]
    fn cut(&self) -> usize {
        self.cut
    }

    /// Rods per unit volume.
    #[getter]
    fn density(&self) -> f64 {
        self.system.density()
    }

    /// What `pickle` rebuilds the rods from: the box and the rods in rgc's
    /// frame, so the round trip is exact.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let raw = self.column3(|r| r.center.into()).into_pyarray(py);
        let state = (
            self.r#box(),
            raw,
            self.column3(|r| r.axis.into()).into_pyarray(py),
            self.lengths(py),
            self.radii(py),
            self.cut,
        );
        crate::pickle::reduce(py, "_rods", state)
    }

    fn __repr__(&self) -> String {
        format!(
            "Rods({} rods in a box {} ({}{}))",
            self.system.len(),
            self.system.domain.sides.map(short).join(","),
            self.system.domain.periodic.name(),
            if self.centred { ", centred" } else { "" }
        )
    }
}

impl PyRods {
    pub fn new(system: RodSystem, cut: usize, centred: bool) -> Self {
        PyRods {
            system: Arc::new(system),
            cut,
            centred,
        }
    }

    /// The box the rods were given in.
    pub fn r#box(&self) -> PyBox {
        PyBox {
            domain: self.system.domain,
            centred: self.centred,
        }
    }

    fn column3(&self, f: impl Fn(&Rod) -> [f64; 3]) -> Array2<f64> {
        let flat: Vec<f64> = self.system.rods.iter().flat_map(f).collect();
        Array2::from_shape_vec((self.system.len(), 3), flat).expect("three values per rod")
    }
}

/// A distribution from a number or a text `VALUE`, `uniform:LO,HI` or `lognormal:MEAN,SD`.
fn dist(obj: &Bound<'_, PyAny>) -> PyResult<Dist> {
    if let Ok(x) = obj.extract::<f64>() {
        return Ok(Dist::Fixed { value: x });
    }
    let text: String = obj
        .extract()
        .map_err(|_| value_error("a size must be a number or a text such as 'uniform:0.8,1.2'"))?;
    Dist::parse(&text).map_err(value_error)
}

/// Random rods of the CLI's ensembles: `density` rods per unit volume, of
/// aspect ratio `gamma` (radius = mean length / (2 gamma)) or of `radius`,
/// isotropic or aligned (`order`, the nematic order parameter, about
/// `director`), reproducibly from `seed` (the same as `rgc sample --seed`;
/// in a centred box the same rods shifted by `-L/2`).
#[pyfunction]
#[pyo3(
    signature = (r#box, density, gamma=None, radius=None, length=None, order=None, director=None, seed=None),
    text_signature = "(box, density, gamma=None, radius=None, length=None, order=None, director=None, seed=1)"
)]
#[allow(clippy::too_many_arguments)]
pub fn generate(
    py: Python<'_>,
    r#box: &PyBox,
    density: f64,
    gamma: Option<f64>,
    radius: Option<&Bound<'_, PyAny>>,
    length: Option<&Bound<'_, PyAny>>,
    order: Option<f64>,
    director: Option<(f64, f64, f64)>,
    seed: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyRods> {
    let seed = crate::seed(seed)?;
    let length = match length {
        Some(l) => dist(l)?,
        None => Dist::Fixed { value: 1.0 },
    };
    let radius = match (radius, gamma) {
        (Some(r), None) => dist(r)?,
        (None, Some(g)) => {
            if !g.is_finite() || g < rgc::rods::MIN_GAMMA {
                return Err(value_error(format!(
                    "gamma must be at least 1 (a rod at least as long as it is wide), got {}",
                    short(g)
                )));
            }
            Dist::Fixed {
                value: length.mean() / (2.0 * g),
            }
        }
        _ => return Err(value_error("give either gamma or radius")),
    };
    let orientation = match (order, director) {
        (None, None) => Orientation::Isotropic,
        (Some(order), d) => Orientation::Aligned {
            order,
            director: d.map_or([0.0, 0.0, 1.0], |d| [d.0, d.1, d.2]),
        },
        (None, Some(_)) => return Err(value_error("a director needs an order parameter")),
    };
    let ensemble = Ensemble {
        domain: r#box.domain,
        density,
        length,
        radius,
        orientation,
    };
    // Too many rods for memory is a MemoryError, before the ensemble's own
    // checks would call it a bad parameter.
    if density.is_finite() && density > 0.0 {
        check_build(ensemble.n_rods())?;
    }
    ensemble.check().map_err(error)?;
    let system = interrupt::run(py, move || ensemble.generate(seed))?.map_err(error)?;
    Ok(PyRods::new(system, 0, r#box.centred))
}
