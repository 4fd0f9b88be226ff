//! Boxes and rods: arrays in, a checked rod system out.

use numpy::ndarray::{Array1, Array2, ArrayView2};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use rgc::Error;
use rgc::rods::ensemble::{Dist, Ensemble, Orientation};
use rgc::rods::{Cut, Domain, Periodic, Rod, RodSystem, wrap};

use crate::value_error;

/// A box `[0, L_x) x [0, L_y) x [0, L_z)` and its periodic axes. A box
/// given as `centred` (HOOMD's convention, `[-L/2, L/2)`) takes points in
/// that frame and shifts them by `L/2`.
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

/// Three sides from a number or a sequence of three.
fn sides(obj: &Bound<'_, PyAny>) -> PyResult<[f64; 3]> {
    if let Ok(l) = obj.extract::<f64>() {
        return Ok([l; 3]);
    }
    let v: Vec<f64> = obj
        .extract()
        .map_err(|_| value_error("box sides must be a number or three numbers"))?;
    <[f64; 3]>::try_from(v.as_slice()).map_err(|_| {
        value_error(format!(
            "box sides must be a number or three numbers, got {}",
            v.len()
        ))
    })
}

#[pymethods]
impl PyBox {
    #[new]
    #[pyo3(signature = (sides, periodic="xyz", centred=false))]
    fn new(sides: &Bound<'_, PyAny>, periodic: &str, centred: bool) -> PyResult<Self> {
        let domain =
            Domain::new(self::sides(sides)?, self::periodic(periodic)?).map_err(value_error)?;
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

    /// Points of shape (N, 3) in this box's frame, in rgc's frame `[0, L)`:
    /// shifted by `L/2` if centred, and wrapped along periodic axes.
    fn wrap<'py>(
        &self,
        py: Python<'py>,
        points: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let p = points3(&points.as_array(), "points")?;
        Ok(self.to_box(&p).into_pyarray(py))
    }

    fn __repr__(&self) -> String {
        let [x, y, z] = self.domain.sides;
        format!(
            "Box(sides=({x}, {y}, {z}), periodic={:?}, centred={})",
            self.domain.periodic.name(),
            if self.centred { "True" } else { "False" }
        )
    }
}

impl PyBox {
    /// Points in rgc's frame.
    fn to_box(&self, p: &Array2<f64>) -> Array2<f64> {
        let mut out = p.clone();
        for mut row in out.rows_mut() {
            for k in 0..3 {
                let l = self.domain.sides[k];
                let x = row[k] + if self.centred { 0.5 * l } else { 0.0 };
                row[k] = if self.domain.wraps(k) { wrap(x, l) } else { x };
            }
        }
        out
    }
}

/// An (N, 3) array of finite numbers, or an error naming it (a NaN would
/// otherwise wrap silently into the box).
fn points3(a: &ArrayView2<'_, f64>, what: &str) -> PyResult<Array2<f64>> {
    if a.ncols() != 3 {
        return Err(value_error(format!(
            "{what} must have shape (N, 3), got {:?}",
            a.shape()
        )));
    }
    if let Some((i, _)) = a
        .rows()
        .into_iter()
        .enumerate()
        .find(|(_, r)| r.iter().any(|x| !x.is_finite()))
    {
        return Err(value_error(format!("{what} row {i} is not finite")));
    }
    Ok(a.to_owned())
}

/// Per-rod values from a number or an (N,) array.
fn per_rod(obj: &Bound<'_, PyAny>, n: usize, what: &str) -> PyResult<Vec<f64>> {
    if let Ok(x) = obj.extract::<f64>() {
        return Ok(vec![x; n]);
    }
    let a: PyReadonlyArray1<'_, f64> = obj.extract().map_err(|_| {
        value_error(format!(
            "{what} must be a number or a float64 array of shape (N,)"
        ))
    })?;
    if a.len() != n {
        return Err(value_error(format!(
            "{what} has {} values for {n} rods",
            a.len()
        )));
    }
    Ok(a.as_array().to_vec())
}

/// Unit directions from quaternions `(w, x, y, z)` (HOOMD's order) rotating
/// `axis`, as the library reads a LAMMPS dump's quaternions.
fn rotate(q: &ArrayView2<'_, f64>, axis: [f64; 3]) -> PyResult<Array2<f64>> {
    if q.ncols() != 4 {
        return Err(value_error(format!(
            "quaternions must have shape (N, 4), got {:?}",
            q.shape()
        )));
    }
    let mut out = Array2::zeros((q.nrows(), 3));
    for (i, row) in q.rows().into_iter().enumerate() {
        let a = rgc::rods::rotate([row[0], row[1], row[2], row[3]], axis)
            .ok_or_else(|| value_error(format!("quaternion {i} is not a rotation")))?;
        for k in 0..3 {
            out[[i, k]] = a[k];
        }
    }
    Ok(out)
}

/// A checked rod system in a box.
#[pyclass(name = "Rods", module = "rgc", frozen)]
#[derive(Clone)]
pub struct PyRods {
    pub system: RodSystem,
    /// Rods whose cores were cut at a wall.
    pub cut: usize,
}

#[pymethods]
impl PyRods {
    /// Rods from arrays: `centres` (N, 3) in the box's frame (wrapped along
    /// periodic axes, so centred boxes and `np.mod` at exactly `L` work),
    /// and either `directions` (N, 3) or `quaternions` (N, 4, `(w, x, y, z)`
    /// rotating `axis`); `lengths` and `radii` are numbers or (N,) arrays.
    /// Cores crossing a wall are cut to the box, as reading a file does.
    #[staticmethod]
    #[pyo3(signature = (r#box, centres, directions=None, quaternions=None, lengths=None, radii=None, axis=(1.0, 0.0, 0.0)))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        r#box: &PyBox,
        centres: PyReadonlyArray2<'_, f64>,
        directions: Option<PyReadonlyArray2<'_, f64>>,
        quaternions: Option<PyReadonlyArray2<'_, f64>>,
        lengths: Option<&Bound<'_, PyAny>>,
        radii: Option<&Bound<'_, PyAny>>,
        axis: (f64, f64, f64),
    ) -> PyResult<Self> {
        let centres = r#box.to_box(&points3(&centres.as_array(), "centres")?);
        let n = centres.nrows();
        let dirs = match (directions, quaternions) {
            (Some(d), None) => points3(&d.as_array(), "directions")?,
            (None, Some(q)) => rotate(&q.as_array(), [axis.0, axis.1, axis.2])?,
            _ => return Err(value_error("give either directions or quaternions")),
        };
        if dirs.nrows() != n {
            return Err(value_error(format!(
                "{} directions for {n} centres",
                dirs.nrows()
            )));
        }
        let lengths = per_rod(
            lengths.ok_or_else(|| value_error("lengths are needed"))?,
            n,
            "lengths",
        )?;
        let radii = per_rod(
            radii.ok_or_else(|| value_error("radii are needed"))?,
            n,
            "radii",
        )?;
        let mut rods = Vec::with_capacity(n);
        let mut cut = 0;
        for i in 0..n {
            let v = |a: &Array2<f64>| nalgebra::Vector3::new(a[[i, 0]], a[[i, 1]], a[[i, 2]]);
            let rod = Rod {
                center: v(&centres),
                axis: v(&dirs),
                length: lengths[i],
                radius: radii[i],
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
        let system = RodSystem::new(r#box.domain, rods).map_err(value_error)?;
        Ok(PyRods { system, cut })
    }

    fn __len__(&self) -> usize {
        self.system.len()
    }

    #[getter(r#box)]
    fn get_box(&self) -> PyBox {
        PyBox {
            domain: self.system.domain,
            centred: false,
        }
    }

    /// Centres in `[0, L)`, shape (N, 3).
    #[getter]
    fn centres<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.column3(|r| r.center).into_pyarray(py)
    }

    /// Unit directions, shape (N, 3).
    #[getter]
    fn directions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.column3(|r| r.axis).into_pyarray(py)
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

    fn __repr__(&self) -> String {
        format!(
            "Rods({} rods in a box {} ({}))",
            self.system.len(),
            self.system.domain.describe(),
            self.system.domain.periodic.name()
        )
    }
}

impl PyRods {
    fn column3(&self, f: impl Fn(&Rod) -> nalgebra::Vector3<f64>) -> Array2<f64> {
        let mut a = Array2::zeros((self.system.len(), 3));
        for (i, r) in self.system.rods.iter().enumerate() {
            let v = f(r);
            for k in 0..3 {
                a[[i, k]] = v[k];
            }
        }
        a
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
/// `director`), reproducibly from `seed` (the same as `rgc sample --seed`).
#[pyfunction]
#[pyo3(signature = (r#box, density, gamma=None, radius=None, length=None, order=None, director=None, seed=1))]
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
    seed: u64,
) -> PyResult<PyRods> {
    let length = match length {
        Some(l) => dist(l)?,
        None => Dist::Fixed { value: 1.0 },
    };
    let radius = match (radius, gamma) {
        (Some(r), None) => dist(r)?,
        (None, Some(g)) => {
            if !g.is_finite() || g < rgc::rods::MIN_GAMMA {
                return Err(value_error(format!(
                    "gamma must be at least 1 (a rod at least as long as it is wide), got {g}"
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
    ensemble.check().map_err(value_error)?;
    let system = py
        .detach(|| ensemble.generate(seed))
        .map_err(|e: Error| value_error(e))?;
    Ok(PyRods { system, cut: 0 })
}
