"""Typed stubs of a scene's tables (``scene.fem``, ``scene.loading.normal``, ...): every table and
every key the command lines accept, with its meaning and SI unit (docs/scenes.md, fem/README.md,
spectral/README.md, docs/meshes.md; the parsers are fem/src/scene/raw.rs, spectral/src/scene.rs
and compare/src/study.rs). At run time each table is a ``cohesive_contact.Table`` view into the
scene, an array of tables (``[[fem.interface_zones]]``) a list of dicts.

A key is typed as the type it reads as when the scene has it, optional or not (the docstring says
which are optional and their defaults). A key that is a Python keyword (``from`` of
``fem.interface_sine`` and ``fem.interface_rough``) is typed on item access: ``sine["from"]``.
``python/tests/test_stubs.py`` keeps these stubs and the parsers in step.
"""

from typing import Any, Dict, Iterator, List, Literal, TypedDict, overload

class _TableView:
    """What every table of a scene has besides its keys (a ``cohesive_contact.Table`` view: a
    change made through it changes the scene)."""

    @property
    def name(self) -> str:
        """The dotted name of the table (``fem.mesh``)."""
    def to_dict(self) -> Dict[str, Any]:
        """The table as a dict (a copy)."""
    def keys(self) -> List[str]: ...
    def __getitem__(self, key: str) -> Any: ...
    def __setitem__(self, key: str, value: Any) -> None: ...
    def __delitem__(self, key: str) -> None: ...
    def __contains__(self, key: str) -> bool: ...
    def __iter__(self) -> Iterator[str]: ...
    def __len__(self) -> int: ...

# ----------------------------------------------------------------------------------------------
# The shared problem, read by both models

class MaterialHalf(_TableView):
    """One isotropic linear-elastic material, plane strain: ``[material.top]`` (the body above
    the interface row, y > 0), ``[material.bottom]`` (below it) or ``[fem.mesh.materials.NAME]``
    (a bulk surface of a Gmsh mesh). All three keys are required."""

    youngs_modulus: float
    """Young's modulus E, > 0 [Pa]."""
    poisson_ratio: float
    """Poisson ratio ν, in [0, 0.5) [-]."""
    density: float
    """Density ρ, > 0 [kg/m^3]."""

class MaterialTable(_TableView):
    """``[material]``: the bulk (FE) or both half-spaces (spectral), plane strain. Either the three
    flat keys (one material everywhere) or the two subtables ``top`` and ``bottom``, not both."""

    youngs_modulus: float
    """Young's modulus E of the one material, > 0 [Pa]."""
    poisson_ratio: float
    """Poisson ratio ν of the one material, in [0, 0.5) [-]."""
    density: float
    """Density ρ of the one material, > 0 [kg/m^3]."""
    top: MaterialHalf
    """Material of the body above the interface row (y > 0); with ``bottom``, instead of the flat
    keys (built-in grid and spectral model only)."""
    bottom: MaterialHalf
    """Material of the body below the interface row (y < 0); with ``top``."""

class InterfaceTable(_TableView):
    """A linear coupled cohesive law (paper eqs. 2-3): ``[interface]`` (optional in the FE model:
    no cohesive interface without it; required by the spectral model) or
    ``[fem.mesh.laws.NAME]`` (the law of one interface curve of a Gmsh mesh). All four keys are
    required."""

    sigma_c: float
    """Cohesive strength σ_c, > 0 [Pa]."""
    delta_c: float
    """Critical opening δ_c, > 0 (G_c = σ_c δ_c / 2) [m]."""
    beta: float
    """Shear/normal coupling β of the traction-separation law, > 0 [-]."""
    kappa: float
    """Parameter κ of the traction-separation law, > 0 [-]."""

class CrackTable(_TableView):
    """``[crack]``: the pre-crack on y = 0, |x − center_x| < half_length (optional in the FE
    model; required by the spectral model)."""

    half_length: float
    """Pre-crack half-length a (0: no pre-crack in the spectral model) [m]."""
    center_x: float
    """Pre-crack centre x_c [m]."""

class FrictionTable(_TableView):
    """``[friction]``: Coulomb friction (static = kinetic) on closed crack faces, the same rule in
    both models."""

    friction_coeff: float
    """Coulomb friction coefficient μ, in [0, 10]; required in the table [-]."""
    contact_friction: Literal["all_faces", "failed_only"]
    """Where friction acts: ``"all_faces"`` (default; every closed face, partly damaged cohesive
    ones included, on top of the cohesive shear, paper §2.3) or ``"failed_only"`` (only where the
    interface has fully failed) [-]."""

class Ramp(_TableView):
    """A history through the ramp of paper eq. (B.1): value(t) = initial + (final − initial)
    S((t − ramp_start)/(ramp_end − ramp_start)), S(s) = s³(10 − 15s + 6s²). All four keys are
    required. Used by ``loading.normal``, ``loading.shear`` and ``fem.boundary.NAME.pressure``."""

    initial: float
    """Value before the ramp [Pa]."""
    final: float
    """Value after the ramp [Pa]."""
    ramp_start: float
    """Start of the ramp t₀, in [0, loading.duration) unless final == initial [s]."""
    ramp_end: float
    """End of the ramp t₁, >= ramp_start (equal: a step) [s]."""

class LoadingTable(_TableView):
    """``[loading]``: the run's duration and the uniform far-field stresses."""

    duration: float
    """Run duration T, > 0: every run goes from t = 0 to T [s]."""
    normal: Ramp
    """Far-field normal stress σ_yy(t), tension positive [Pa] (optional in the FE model, default
    0; required by the spectral model)."""
    shear: Ramp
    """Far-field shear stress σ_xy(t) [Pa] (optional in the FE model, default 0; required by the
    spectral model)."""

# ----------------------------------------------------------------------------------------------
# [fem]: the FE model

class FemMeshLaws(_TableView):
    """``[fem.mesh.laws]``: per interface curve of the mesh, by its name in the file, its own
    cohesive law (the other curves keep ``[interface]``); not with ``[[fem.interface_zones]]``."""

    def __getattr__(self, name: str) -> InterfaceTable:
        """The cohesive law of the interface curve ``name``."""
    def __getitem__(self, key: str) -> InterfaceTable: ...

class FemMeshMaterials(_TableView):
    """``[fem.mesh.materials]``: per bulk surface of the mesh (listed in ``fem.mesh.bulk``), by its
    name in the file, its own material (a surface without an entry takes ``[material]``); needs
    ``[fem.boundary]``, and ``compare`` refuses it."""

    def __getattr__(self, name: str) -> MaterialHalf:
        """The material of the bulk surface ``name``."""
    def __getitem__(self, key: str) -> MaterialHalf: ...

class FemMeshTable(_TableView):
    """``[fem.mesh]``: the FE body is a Gmsh mesh (MSH 4.1, T3 and/or Q4) instead of the built-in
    grid, whose keys (``x_range``, ``y_range``, ``element_size``, ``upper_offset``,
    ``interface_polyline``, ``interface_sine``, ``interface_rough``) are then refused
    (docs/meshes.md)."""

    file: str
    """The mesh file, relative to the scene file's folder; required [-]."""
    bulk: List[str]
    """Physical surfaces that make the body (default: every element) [-]."""
    pre_crack: List[str]
    """Physical curves: crack faces free from t = 0; goes with ``[crack]``, whose extent they must
    match [-]."""
    interface: List[str]
    """Physical curves: facets where cohesive elements are inserted (needs ``[interface]``) [-]."""
    unit: float
    """Length of one unit of the file's coordinates, > 0 (default 1; 1e-3 for a mesh drawn in
    millimetres) [m]."""
    laws: FemMeshLaws
    """Per interface curve, by name: its own cohesive law."""
    materials: FemMeshMaterials
    """Per bulk surface, by name: its own material."""

class FemParaviewTable(_TableView):
    """``[fem.paraview]``: ParaView field snapshots of the ``fem`` command (none without the
    table)."""

    interval: float
    """Simulated time between two snapshots, rounded to whole steps, in (0, loading.duration];
    required (more than 10 000 files are refused) [s]."""

class BoundaryComponent(_TableView):
    """One component (``x`` or ``y``) of a part's boundary condition, through the ramp of
    eq. (B.1). All five keys are required."""

    kind: Literal["displacement", "traction", "force"]
    """``"displacement"`` [m], ``"traction"`` [Pa] (on a side or curve) or ``"force"`` [N/m] (per
    unit thickness, on a physical point of a mesh) [-]."""
    initial: float
    """Value before the ramp, by ``kind`` [m], [Pa] or [N/m]."""
    final: float
    """Value after the ramp, by ``kind`` [m], [Pa] or [N/m]."""
    ramp_start: float
    """Start of the ramp, in [0, loading.duration) unless final == initial [s]."""
    ramp_end: float
    """End of the ramp, >= ramp_start [s]."""

class BoundaryPart(_TableView):
    """``[fem.boundary.NAME]``: the conditions of one side, curve or point; a part not listed is
    free. At least one key must be given."""

    x: BoundaryComponent
    """Condition on the x component [m], [Pa] or [N/m]."""
    y: BoundaryComponent
    """Condition on the y component [m], [Pa] or [N/m]."""
    pressure: Ramp
    """Uniform pressure along the inward normal, > 0 compresses (sides and curves of the outer
    boundary) [Pa]."""
    absorbing: bool
    """Viscous dashpots (Lysmer-Kuhlemeyer, ρc_d normal, ρc_s tangential) that let waves out;
    not with an imposed displacement, not on a point (default false) [-]."""
    far_field: bool
    """The part carries the traction of the far-field stress of ``[loading]``; replaces ``x``,
    ``y`` and ``pressure`` (default false) [-]."""

class FemBoundaryTable(_TableView):
    """``[fem.boundary]``: side-wise boundary conditions replacing the Westergaard displacement
    field (required without a centre pre-crack inside the domain); at most 80 parts, applied in
    the order bottom, right, top, left, then the other names."""

    bottom: BoundaryPart
    """The bottom side of the built-in grid (or a mesh curve of that name)."""
    right: BoundaryPart
    """The right side of the built-in grid (or a mesh curve of that name)."""
    top: BoundaryPart
    """The top side of the built-in grid (or a mesh curve of that name)."""
    left: BoundaryPart
    """The left side of the built-in grid (or a mesh curve of that name)."""

    def __getattr__(self, name: str) -> BoundaryPart:
        """A physical curve or point of the ``[fem.mesh]`` file, by its name in the file."""
    def __getitem__(self, key: str) -> BoundaryPart: ...

class InterfaceSine(_TableView):
    """``fem.interface_sine``: the interface row follows y = amplitude sin(π(|x − x_c| −
    from)/half_period) for from <= |x − x_c| <= to, y = 0 elsewhere (paper Section 4); not with
    ``interface_polyline`` or ``interface_rough``. All four keys are required; ``from`` is a
    Python keyword: read it as ``sine["from"]``."""

    amplitude: float
    """Amplitude A of the sine, finite [m]."""
    half_period: float
    """Half period of the sine, > 0 [m]."""
    to: float
    """Outer end of each branch, distance from crack.center_x, > from and within fem.x_range [m]."""

    @overload
    def __getitem__(self, key: Literal["from"]) -> float:
        """``from``: inner end of each branch, distance from crack.center_x, >= 0 [m]."""
    @overload
    def __getitem__(self, key: str) -> Any: ...

class InterfaceRough(_TableView):
    """``fem.interface_rough``: the interface row follows a self-affine rough profile on both sides
    of the crack centre (each side an independent draw), zero at both ends (docs/scenes.md);
    not with ``interface_polyline``, ``interface_sine`` or ``[fem.mesh]``. Every key is required
    except ``taper``; ``from`` is a Python keyword: read it as ``rough["from"]``."""

    hurst: float
    """Hurst exponent H in (0, 1): the power spectrum is C(q) ∝ q^-(1+2H) [-]."""
    rms_slope: float
    """RMS of dy/dx between node columns over both sides, > 0 [-]."""
    seed: int
    """Seed of the random phases (ChaCha8), an integer >= 0 [-]."""
    to: float
    """Outer end of each side, distance from crack.center_x, > from, on a node column [m]."""
    wavelength_min: float
    """Shortest wavelength, at least 4 fem.element_size [m]."""
    wavelength_max: float
    """Longest wavelength, above wavelength_min and at most to − from [m]."""
    taper: float
    """Length of the sin² ramps that bring the row to 0 at both ends (default wavelength_max/4;
    at least one element, at most (to − from)/2) [m]."""

    @overload
    def __getitem__(self, key: Literal["from"]) -> float:
        """``from``: inner end of each side, distance from crack.center_x, >= 0, on a node column
        [m]."""
    @overload
    def __getitem__(self, key: str) -> Any: ...

class InterfaceZone(TypedDict):
    """One ``[[fem.interface_zones]]`` entry: facets whose midpoint lies in ``x_range`` use this
    cohesive law instead of ``[interface]`` (paper Section 4's weak interface); zones may not
    overlap. All five keys are required."""

    x_range: List[float]
    """[x0, x1] with x0 < x1, inside fem.x_range (interface coordinate on a mesh) [m]."""
    sigma_c: float
    """Cohesive strength σ_c of the zone, > 0 [Pa]."""
    delta_c: float
    """Critical opening δ_c of the zone, > 0 [m]."""
    beta: float
    """Coupling β of the zone, > 0 [-]."""
    kappa: float
    """Parameter κ of the zone, > 0 [-]."""

class FemTable(_TableView):
    """``[fem]``: the FE model's discretisation, options, boundary conditions and diagnostics
    (fem/README.md, "Scene keys")."""

    x_range: List[float]
    """Domain [x0, x1] of the built-in grid, x1 > x0; required without ``[fem.mesh]``, refused
    with it [m]."""
    y_range: List[float]
    """Domain [y0, y1] of the built-in grid, y0 < 0 < y1 (y = 0 is the interface row); required
    without ``[fem.mesh]``, refused with it [m]."""
    element_size: float
    """FE element size h: width and both heights multiples of it, crack tips on nodes; required
    without ``[fem.mesh]``, refused with it [m]."""
    mesh: FemMeshTable
    """A Gmsh mesh instead of the built-in grid."""
    model: Literal["hybrid", "standard"]
    """``"hybrid"`` (default: node-to-segment contact + cohesive law without compression) or
    ``"standard"`` (contact through the cohesive law's compression penalty, paper eq. 4) [-]."""
    time_step_safety: float
    """Safety factor α of the stable step Δt = α h_min/c_d f(β_p), in (0, 0.95] (default 0.5);
    not with ``time_step`` [-]."""
    time_step: float
    """Requested time step Δt, > 0, refused above the α = 0.95 limit; not with
    ``time_step_safety`` [s]."""
    eps_n: float
    """Normal contact penalty ε_n, >= 0 (default 0; > 0 needed with contact) [Pa/m]."""
    eps_t: float
    """Tangential contact penalty ε_t, >= 0 (default eps_n) [Pa/m]."""
    t_star: float
    """Prakash regularisation time t* of the friction pressure (paper eq. 14), >= 0 (default 0:
    plain Coulomb) [s]."""
    lateral_contraction: bool
    """Add u_x −= ν (x − x_c) σ_yy/(2G) to the Westergaard boundary field (default true) [-]."""
    mode_ii_uy: bool
    """Add the mode-II part of u_y that paper eq. (C.9) drops (default false) [-]."""
    output_interval: float
    """Sampling interval of the records, in (0, loading.duration]; required [s]."""
    insertion_rule: Literal["max", "mean"]
    """Insertion criterion over the facet's two Gauss points: ``"max"`` (default, paper App. A) or
    ``"mean"`` (Akantu) [-]."""
    damping: Literal["none", "contact_only", "inserted", "contact_and_inserted", "all_cohesive"]
    """Which interface nodes are damped (default ``"none"``; ``"all_cohesive"`` is the paper's
    rule); docs/fem-model.md §6 [-]."""
    damping_factor: float
    """Velocity factor per step on the damped set, in (0, 1] (default 0.99); only with
    ``damping``, not with ``damping_time`` [-]."""
    damping_time: float
    """Decay time τ of the damped velocities, factor exp(−Δt/τ) per step, > 0; only with
    ``damping``, not with ``damping_factor`` [s]."""
    damping_window: float
    """How long after its insertion a cohesive element's nodes are damped, > 0; required by, and
    only with, ``damping = "inserted"`` or ``"contact_and_inserted"`` [s]."""
    max_gap: float
    """Contact detection distance d_max, > 0 (default h; on a mesh the shortest interface
    facet) [m]."""
    projection_tolerance: float
    """Node-to-segment projection tolerance ε on ξ, in [0, 0.5) (default 1e-3) [-]."""
    upper_offset: float
    """x-shift of the upper block's nodes, in [0, 1) element sizes h (full-width pre-crack only;
    default 0) [-]."""
    interface_polyline: List[List[float]]
    """[[x, y], ...], x strictly increasing: the interface row follows this polyline (y = 0
    outside) [m]."""
    interface_sine: InterfaceSine
    """A sinusoidal interface row (paper Section 4)."""
    interface_rough: InterfaceRough
    """A self-affine rough interface row (Section 5 outlook)."""
    interface_zones: List[InterfaceZone]
    """``[[fem.interface_zones]]``: stretches of the interface row with their own cohesive law."""
    contact_surface: Literal["all", "zones"]
    """Faces of the contact detection surface: ``"all"`` (default: pre-crack faces and both faces
    of every inserted element, eq. 10) or ``"zones"`` (only the inserted facets of
    ``interface_zones`` or of the curves of ``[fem.mesh.laws]``, eq. 16) [-]."""
    residual_stress_x: List[float]
    """[x0, x1] inside fem.x_range: record the residual stress of eq. (17) over the + facets with
    midpoint in it, every sample (``residual_stress.csv``) [m]."""
    kkt_metric: bool
    """Record the KKT conditions on the crack faces of the contact surface every sample
    (``kkt.csv``; default false) [-]."""
    snapshot_times: List[float]
    """Increasing times in (0, loading.duration] of stress snapshots (``field.csv``,
    ``profile.csv``; default none) [s]."""
    snapshot_window: List[List[float]]
    """[[x0, x1], [y0, y1]] inside the domain: the element stresses of a snapshot (default the
    domain) [m]."""
    probes: List[List[float]]
    """[[x, y], ...] inside the body: the nearest nodes' displacements are recorded [m]."""
    boundary: FemBoundaryTable
    """Side-wise boundary conditions instead of the Westergaard field."""
    paraview: FemParaviewTable
    """ParaView field snapshots."""

# ----------------------------------------------------------------------------------------------
# [spectral]: the spectral boundary-integral model

class Nucleation(_TableView):
    """``spectral.nucleation``: a cos² bump added to the shear load s_xy, constant in time; it
    must fit inside the periodic length. All three keys are required."""

    shear: float
    """Peak added shear stress, finite [Pa]."""
    center: float
    """Centre x of the bump [m]."""
    half_width: float
    """Half-width of the bump, > 0 (zero for |x − center| >= half_width) [m]."""

class SpectralTable(_TableView):
    """``[spectral]``: the spectral model's discretisation and options (spectral/README.md)."""

    length: float
    """Periodic length X, > 0 and above 4 crack.half_length; required [m]."""
    grid_points: int
    """Number of grid points N, an even integer in [4, 2^24]; required [-]."""
    cs_dt_over_dx: float
    """CFL number c_s Δt/Δx, in (0, 0.5]; exactly one of it and ``time_step`` [-]."""
    time_step: float
    """Time step Δt, with c_s Δt/Δx in (0, 0.5]; exactly one of it and ``cs_dt_over_dx`` [s]."""
    kernel_cutoff: float
    """Kernel truncation tcut in T = |k| c_s t (direct path), fit range (fast path), in
    (0, 1000]; required [-]."""
    t_star: float
    """Prakash regularisation time t*, >= 0 (0: plain Coulomb); required [s]."""
    output_interval: float
    """Interval between contact-mean records, in (0, loading.duration]; required [s]."""
    field_output_interval: float
    """Interval between space-time field snapshots, in (0, loading.duration] (default: none) [s]."""
    convolution: Literal["fast", "direct"]
    """History convolution: ``"fast"`` (default: sum of exponentials) or ``"direct"`` (the
    reference, truncated at tcut) [-]."""
    fast_tolerance: float
    """Largest error of the fast path's kernel fit on [0, tcut] relative to max|K|, in
    [1e-10, 1e-2] (default 1e-5) [-]."""
    fast_storage: Literal["f64", "f32"]
    """How the fast path keeps its recursion states from step to step: ``"f64"`` (default) or
    ``"f32"`` (rounded to single precision: two thirds of the memory; fast path only) [-]."""
    contact: bool
    """Contact (no interpenetration) on broken points (default true; off only for verification
    set-ups) [-]."""
    nucleation: Nucleation
    """A shear-load perturbation for nucleation (default none)."""
    initial_interface: Literal["pre_crack", "broken"]
    """Points broken at t = 0: ``"pre_crack"`` (default: |x − center_x| < a) or ``"broken"``
    (every point: a frictional or free fault, for verification) [-]."""

# ----------------------------------------------------------------------------------------------
# [compare]: the harness

class CompareTable(_TableView):
    """``[compare]``: what the harness's jobs run (docs/scenes.md)."""

    friction_coeffs: List[float]
    """Friction coefficients μ the FE-versus-spectral gate runs, distinct, each valid in both
    models [-]."""
    models: List[Literal["standard", "hybrid"]]
    """FE models the Section 4 study runs, in order, no repeats [-]."""
    snapshot_t_over_T: float
    """Time of the Section 4 maps and profiles over the duration T, in (0, 1] [-]."""
