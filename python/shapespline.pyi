"""Type stubs of the shapespline extension module (python/src, pybind11). Reference: docs/python.md.

Shape-parametric spline curves and surfaces (Xu-Wang extended cubic B-splines of degree 4-6,
alpha-EB interpolating curves and surfaces, GB-splines, UBP, GUBP, B-splines on knot vectors),
evaluated on a Vulkan GPU (fp32 or fp64) or on the CPU fp64 path. Every job goes through the
library's sampling layer: device="auto" uses the GPU where it can and falls back to the CPU with a
reason (Report.fallbacks); require=True turns a fallback into DeviceError.

Array conventions: sampled and evaluated points are always 3-D (2-D curves have z = 0); float64
for precision="double", float32 for precision="float"; every array is C-contiguous and owned by
NumPy (no per-point Python objects).
"""
from typing import Any, Iterator, Literal, Optional, Sequence, Tuple, Union, overload

import os
import numpy as np
import numpy.typing as npt

__version__: str
git_commit: str
__license__: str  # the SPDX id of the licence, "Apache-2.0"

Device = Literal["auto", "vulkan", "gpu", "cpu"]
PrecisionName = Literal["double", "float", "float64", "float32", "fp64", "fp32"]
ArrayLike = npt.ArrayLike
Fields = Union[str, Sequence[str], None]

class ModelError(ValueError):
    """A model or parameter that breaks a rule of docs/format.md / docs/math.md.

    field: JSON-path-like name ("alpha[3]", "points[2][1]", "lambda"); value: the offending value as
    text; rule: the rule. str(e) names all three."""

    field: str
    value: str
    rule: str

class DeviceError(RuntimeError):
    """A Vulkan failure (with a hint what to change), or a CPU fallback refused by require=True
    (fallback_refused is then True)."""

    fallback_refused: bool

class Report:
    """What a job did."""

    device: str
    """'cpu' or the Vulkan device's name."""
    gpu: bool
    computed_precision: Literal["double", "float"]
    """The CPU path computes in fp64 whatever the output precision."""
    output_precision: Literal["double", "float"]
    fallbacks: list[str]
    """Why the GPU was not used, in the order found (empty when it was)."""
    net_scale_exponent: int
    band_rows: int  # GPU grids of nets over one device buffer: patch rows per band; 0 otherwise
    """The GPU evaluated 2^k * net (exact power-of-two scaling of extreme nets)."""

class ChunkIterator(Iterator[dict[str, Any]]):
    """Chunks of a grid job (Curve/Surface.sample_chunks), produced by a thread into a bounded queue.

    Each chunk is a dict: first_item, item_count, first_row, row_count (0: whole items),
    first_point (index of the chunk's first point in the whole job) and one (n, 3) array per
    requested field. Chunks come in item order; concatenated they are the job's points in the order
    of sample(...).reshape(-1, 3). Use as a context manager, or call close(), to cancel early."""

    def __iter__(self) -> ChunkIterator: ...
    def __next__(self) -> dict[str, Any]: ...
    def close(self) -> None:
        """Cancel the job; the producer stops at its next chunk."""
    def __enter__(self) -> ChunkIterator: ...
    def __exit__(self, *args: Any) -> None: ...
    @property
    def report(self) -> Optional[Report]:
        """The job's Report once the producer finished, else None."""

class _Model:
    @property
    def construction(self) -> str:
        """extended_bspline, alpha_eb, gb, ubp, gubp or bspline."""
    @property
    def degree(self) -> int:
        """Xu-Wang degree 4..6 (extended_bspline, alpha_eb), else 0."""
    @property
    def mu(self) -> npt.NDArray[np.float64]:
        """GUBP half vector mu_0..mu_floor(k/2) (empty for other constructions)."""
    @property
    def alpha(self) -> npt.NDArray[np.float64]:
        """alpha_eb tensions, one per control point (row-major for surfaces); empty otherwise."""
    @property
    def uses_knot_vector(self) -> bool:
        """True for a bspline with a knot vector (the parameter is then the knot parameter)."""
    @property
    def item_count(self) -> int:
        """Items of a grid job: spans (curves) or patches (surfaces), in sample() order."""
    lambda_: float
    """The global shape parameter lambda; assigning it is set_lambda."""
    @property
    def alpha_nodes(self) -> npt.NDArray[np.float64]:
        """alpha_eb: node_j = C_j(0) of the base curve/surface per vertex, (N, 3)."""
    @property
    def alpha_v(self) -> npt.NDArray[np.float64]:
        """alpha_eb: the V point of each vertex, (N, 3)."""
    def set_lambda(self, lambda_: float) -> None:
        """Set lambda. ModelError (field 'lambda') when out of range; nothing changes then. On a
        resident GPU model only the parameter block is rewritten (no net upload)."""
    def set_mu(self, mu: ArrayLike) -> None:
        """Set the GUBP half vector (same order)."""
    def plan(self, device: Device = "auto", precision: PrecisionName = "double", require: bool = False) -> Report:
        """The Report a job would get, without running it."""
    def upload_stats(self, precision: PrecisionName = "float") -> dict[str, Any]:
        """Counters of the resident GPU model of one precision: resident (bool), mirrors_built (full
        net uploads so far), net_bytes, net_writes, param_bytes, param_writes, vertex_passes."""
    def to_dict(self) -> dict[str, Any]:
        """The model with the keys of the model file format (docs/format.md)."""
    def save(self, path: str) -> None:
        """Write the model file (JSON)."""

class Curve(_Model):
    """A curve model. Built from keywords (the model file's keys), from_dict(), or load()."""

    def __init__(
        self,
        points: ArrayLike,
        *,
        construction: str = "extended_bspline",
        degree: Optional[int] = None,
        order: Optional[int] = None,
        lambda_: Optional[float] = None,
        mu: Optional[ArrayLike] = None,
        alpha: Union[float, ArrayLike, None] = None,
        closed: Optional[bool] = None,
        knots: Optional[ArrayLike] = None,
        weights: Optional[ArrayLike] = None,
    ) -> None:
        """points: (n, 2) or (n, 3); alpha: a scalar or one value per point; knots: span boundaries
        (extended_bspline, gb) or the knot vector (bspline); weights: one positive value per point of
        a bspline with a knot vector (a rational B-spline). Validated like a model file (ModelError
        naming the field)."""
    @staticmethod
    def from_dict(model: dict[str, Any]) -> Curve:
        """A curve from a dict with the keys of a model file (NumPy arrays allowed as values)."""
    @property
    def kind(self) -> Literal["curve"]: ...
    @property
    def points(self) -> npt.NDArray[np.float64]:
        """Control points, (n, dimension)."""
    @property
    def dimension(self) -> int: ...
    @property
    def closed(self) -> bool: ...
    @property
    def order(self) -> int: ...
    @property
    def knots(self) -> npt.NDArray[np.float64]: ...
    @property
    def weights(self) -> npt.NDArray[np.float64]:
        """Weights of a rational bspline (empty: not rational)."""
    @property
    def spans(self) -> Tuple[int, int]:
        """Valid span indices (first, last), inclusive."""
    @property
    def parameter_range(self) -> Tuple[float, float]:
        """(u_min, u_max) of the global parameter."""
    @overload
    def sample(self, grid: Optional[int] = None, samples: Optional[int] = None, *, fields: Fields = None,
               device: Device = "auto", precision: PrecisionName = "double", require: bool = False,
               first_item: int = 0, item_count: int = 0, chunk_points: int = 0,
               report: Literal[False] = False) -> dict[str, npt.NDArray[Any]]: ...
    @overload
    def sample(self, grid: Optional[int] = None, samples: Optional[int] = None, *, fields: Fields = None,
               device: Device = "auto", precision: PrecisionName = "double", require: bool = False,
               first_item: int = 0, item_count: int = 0, chunk_points: int = 0,
               report: Literal[True] = ...) -> Tuple[dict[str, npt.NDArray[Any]], Report]: ...
    def sample(self, grid=None, samples=None, *, fields=None, device="auto", precision="double", require=False,
               first_item=0, item_count=0, chunk_points=0, report=False):  # type: ignore[no-untyped-def]
        """S samples per span (default 64), t_s = s/(S-1), both ends included.

        fields: 'point', 'd1', 'd2' (derivatives w.r.t. the global parameter) or 'all'. Returns
        {field: array (items, S, 3)}; items = spans (first_item, item_count select a range). The
        arrays are allocated once and written straight from each chunk (GIL released)."""
    def sample_chunks(self, grid: Optional[int] = None, samples: Optional[int] = None, *, fields: Fields = None,
                      device: Device = "auto", precision: PrecisionName = "double", require: bool = False,
                      first_item: int = 0, item_count: int = 0, chunk_points: int = 0,
                      queue: int = 2) -> ChunkIterator:
        """The same job as an iterator of chunks in bounded memory: at most queue + 2 chunks of
        chunk_points points (default: 2^15 on the CPU, 4 MiB planes on the GPU) exist at once."""
    def project(self, points: ArrayLike, *, threads: int = 0, tolerance: float | None = None) -> dict[str, Any]:
        """Closest points (docs/math.md §15): for each row of points (n, 3), the nearest point of the
        curve: point (n, 3), t (n,), distance (n,); fp64, CPU."""
    def evaluate(self, params: Optional[ArrayLike] = None, *, span: Optional[ArrayLike] = None,
                 t: Optional[ArrayLike] = None, device: Device = "auto", precision: PrecisionName = "double",
                 require: bool = False, report: bool = False,
                 fields: Optional[Union[str, Sequence[str]]] = None) -> Any:
        """evaluate(u) at global parameters, or evaluate(span=..., t=...) at local ones: dict point,
        d1, d2, each (n, 3). A sample outside the model raises ValueError naming params[i]. fields:
        only those (and the point); 'point' and 'd1' alone run the lean list kernel."""
    def set_alpha(self, value: Union[float, ArrayLike], index: Optional[int] = None) -> None:
        """alpha of vertex `index`, or of every vertex (a scalar or one value per point)."""
    def set_control_point(self, index: int, point: ArrayLike) -> None:
        """Move one control point (dimension coordinates); the GPU rewrites only the changed net entries."""
    def copy(self) -> Curve:
        """An independent copy without a resident GPU model."""
    def gb_lambda_path(self, span: int, t: ArrayLike) -> dict[str, npt.NDArray[np.float64]]:
        """gb curves: the straight lambda-paths of a span at local t: c0 (lambda = 0), e (lambda -> inf),
        c_minus8 (lambda = -8), each (len(t), 2); C(lambda, t) = w c0 + (1 - w) e, w = 12/(12 + lambda)."""
    def gb_span_points(self, span: int, lambda_: float, t: ArrayLike) -> npt.NDArray[np.float64]:
        """gb curves: C_span(lambda, t), (len(t), 2)."""
    def gb_constrained_modify(self, span: int, target: ArrayLike) -> dict[str, Any]:
        """gb curves: the lambda0 that makes span pass through the 2-D target (docs/math.md 7.2):
        reachable, reason, t0, lambda0, w, all_solutions, curve (the modified Curve or None)."""
    def unclamp_right(self, new_knots: ArrayLike) -> dict[str, npt.NDArray[np.float64]]:
        """bspline curves: Algorithm U on new right knots: points, knots."""
    def extend(self, targets: ArrayLike, u: Optional[ArrayLike] = None) -> dict[str, Any]:
        """bspline curves: extension to target points (chord-length parameters unless u is given):
        curve (the extended Curve), u, unclamp_knots, unclamped_points, knots_normalized."""

class Surface(_Model):
    """A surface model. Built from keywords (the model file's keys), from_dict(), or load()."""

    def __init__(
        self,
        points: ArrayLike,
        *,
        construction: str = "extended_bspline",
        degree: Optional[int] = None,
        order: Union[int, Sequence[int], None] = None,
        lambda_: Optional[float] = None,
        mu: Optional[ArrayLike] = None,
        alpha: Union[float, ArrayLike, None] = None,
        closed: Union[bool, Sequence[bool], None] = None,
        knots: Optional[Sequence[ArrayLike]] = None,
        weights: Optional[ArrayLike] = None,
    ) -> None:
        """points: (rows, cols, 3); closed: a bool or (closed_u, closed_v); alpha: a scalar or
        (rows, cols); order [k, l] and knots [U, V] for bspline; weights (rows, cols) for a rational
        bspline."""
    @staticmethod
    def from_dict(model: dict[str, Any]) -> Surface: ...
    @property
    def kind(self) -> Literal["surface"]: ...
    @property
    def points(self) -> npt.NDArray[np.float64]:
        """Control net, (rows, cols, 3)."""
    @property
    def shape(self) -> Tuple[int, int]: ...
    @property
    def closed(self) -> Tuple[bool, bool]: ...
    @property
    def order(self) -> Tuple[int, int]: ...
    @property
    def knots(self) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    @property
    def patches(self) -> Tuple[Tuple[int, int], Tuple[int, int]]:
        """((first_u, last_u), (first_v, last_v)) valid patch indices, inclusive."""
    @property
    def parameter_range(self) -> Tuple[Tuple[float, float], Tuple[float, float]]: ...
    def sample(self, grid: Union[int, Tuple[int, int], None] = None, samples: Optional[int] = None, *,
               fields: Fields = None, device: Device = "auto", precision: PrecisionName = "double",
               require: bool = False, first_item: int = 0, item_count: int = 0, chunk_points: int = 0,
               report: bool = False) -> Any:
        """Su x Sv samples per patch (default 16 x 16), u_a = a/(Su-1), v_b = b/(Sv-1).

        fields: 'point', 'du', 'dv', 'duu', 'duv', 'dvv', 'normal' or 'all'. Returns {field: array
        (patches, Su, Sv, 3)}, patches row-major (u outer); with report=True also the Report."""
    def sample_chunks(self, grid: Union[int, Tuple[int, int], None] = None, samples: Optional[int] = None, *,
                      fields: Fields = None, device: Device = "auto", precision: PrecisionName = "double",
                      require: bool = False, first_item: int = 0, item_count: int = 0, chunk_points: int = 0,
                      queue: int = 2) -> ChunkIterator:
        """As Curve.sample_chunks."""
    def project(self, points: ArrayLike, *, threads: int = 0, tolerance: float | None = None) -> dict[str, Any]:
        """Closest points (docs/math.md §15): for each row of points (n, 3), the nearest point of the
        surface (inside its trim loops): point (n, 3), uv (n, 2), distance (n,), signed_distance (n,)
        (the side of the normal), normal (n, 3); fp64, CPU."""
    def evaluate(self, params: Optional[ArrayLike] = None, *, patch: Optional[ArrayLike] = None,
                 uv: Optional[ArrayLike] = None, device: Device = "auto", precision: PrecisionName = "double",
                 require: bool = False, report: bool = False,
                 fields: Optional[Union[str, Sequence[str]]] = None) -> Any:
        """evaluate((n, 2) global (U, V)) or evaluate(patch=(n, 2), uv=(n, 2)): dict point, du, dv,
        duu, duv, dvv, normal, each (n, 3); partials w.r.t. the local patch parameters. fields: only
        those (and the point); 'point', 'du' and 'dv' alone run the lean list kernel."""
    def tessellate(self, rate: int = 8, *, device: Device = "auto", precision: PrecisionName = "float",
                   require: bool = False, report: bool = False) -> Any:
        """Watertight triangle mesh at `rate` segments per patch side (uniform constructions):
        (vertices (V, 8) float32 [x, y, z, nx, ny, nz, U, V], indices (T, 3) uint32). On the GPU the
        library's tessellator on the resident model; on the CPU the same topology evaluated in fp64."""
    def set_alpha(self, value: Union[float, ArrayLike], index: Optional[Tuple[int, int]] = None) -> None:
        """alpha of vertex (i, j), or of every vertex (a scalar or a (rows, cols) array)."""
    def set_control_point(self, i: int, j: int, point: ArrayLike) -> None:
        """Move control point (i, j)."""
    def copy(self) -> Surface: ...
    def extend_u(self, target_curves: Sequence[ArrayLike], u: Optional[ArrayLike] = None) -> dict[str, Any]:
        """bspline surfaces: extension in u to target curves (each `cols` control points):
        surface, u, u_per_column, knots_normalized_u."""

def load(path: str) -> Union[Curve, Surface]:
    """A model file (docs/format.md). FileNotFoundError when missing, ModelError when invalid."""

def from_dict(model: dict[str, Any]) -> Union[Curve, Surface]:
    """A model from a dict with the keys of a model file."""

def sample_many(models: Sequence[Union[Curve, Surface, dict[str, Any], str, "os.PathLike[str]"]],
                grid: Union[int, Tuple[int, int], None] = None, *, fields: Fields = None, device: str = "auto",
                precision: str = "double", require: bool = False, errors: str = "raise",
                report: bool = False) -> list[Any]:
    """Each model sampled whole, as its sample() would, through one device and its compiled pipelines:
    a list of sample() dicts ((dict, Report) pairs with report=True). A failing model's exception
    carries the note 'sample_many: models[k]'; errors='keep' puts it in the model's place and
    samples the others."""

class Part:
    """A part `shapespline import` wrote (DIR/part.json): its faces, edges and shells."""

    faces: list[int]
    """The ids of the faces that imported, in the manifest's order."""
    edges: int
    skipped: int
    """Faces that did not convert at import (part.json says why)."""
    diagonal: float
    """The diagonal of the box around every face's control points."""

    def mesh(self, *, deflection: Optional[float] = None, relative_deflection: Optional[float] = None,
             angle: float = 0.5, max_triangles: int = 50_000_000, device: str = "auto", precision: str = "double",
             require: bool = False, threads: int = 0, with_report: bool = False) -> dict[str, Any]:
        """The watertight mesh (docs/cad.md 'Meshing a part'): positions (N, 3) float64, normals (N, 3),
        triangles (M, 3) uint32, face_ids (M,) int32, open_edges, non_manifold_edges, deflection, device
        (and report with with_report). deflection in model units or relative_deflection of the diagonal
        (default 1e-3); ValueError past max_triangles."""
    def sample(self, grid: Union[int, tuple[int, int], None] = None, *, fields: Union[str, Sequence[str], None] = None,
               device: str = "auto", precision: str = "double", require: bool = False,
               report: bool = False) -> Any:
        """The trimmed point cloud (docs/cad.md 'Sampling a part'): each face's grid with only the samples
        inside its trim loops, face after face: uv (K, 2) float64, face_ids (K,) int32 and each field
        (K, 3). report=True: (dict, Report)."""
    def project(self, points: ArrayLike, *, threads: int = 0, tolerance: float | None = None) -> dict[str, Any]:
        """Closest points (docs/math.md §15) on the faces, inside their trim loops: point (n, 3),
        uv (n, 2), face_ids (n,) int32, distance (n,), signed_distance (n,) (outside positive on a
        closed part), normal (n, 3); fp64, CPU."""

def load_part(dir: str) -> Part:
    """A part `shapespline import` wrote: DIR or DIR/part.json."""

def devices() -> str:
    """The Vulkan devices, the one a job would use, fp64 support and limits (as `shapespline info`)."""

def basis(family: str, t: ArrayLike, *, degree: int = 0, order: int = 0, lambda_: float = 0.0,
          mu: Optional[ArrayLike] = None) -> dict[str, npt.NDArray[np.float64]]:
    """Span basis B_0..B_{m-1} at t (as `shapespline basis`): values, d1, d2, each (len(t), m).
    family: xuwang (= extended_bspline; degree), gb, ubp (order 2..10), gubp (order, mu), bspline
    (order), singular_blend (m = 1)."""

def bell(family: str, x: ArrayLike, *, degree: int = 0, order: int = 0, lambda_: float = 0.0,
         mu: Optional[ArrayLike] = None) -> dict[str, npt.NDArray[np.float64]]:
    """The bell function N(x) on [0, m] assembled from the span basis: N, dN, each (len(x),)."""

def ubp_doubled_knot_coefficients(order: int, lambda_: float) -> npt.NDArray[np.float64]:
    """Theorem-1 coefficients lambda_{0,k}..lambda_{k,k} of UBP order k."""
