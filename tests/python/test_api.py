"""The Python API: construction from keywords, the C++ validation's messages as
exceptions, argument checking, broadcasting, dtypes, helpers, tables and the dual BCSDF."""

import math

import numpy as np
import pytest

import hairscatter as hs

RNG = np.random.default_rng(7)


def directions(n):
    w = RNG.normal(size=(n, 3))
    return w / np.linalg.norm(w, axis=1, keepdims=True)


ALL_MODELS = [
    ("Chiang", lambda dt: hs.Chiang(sigma_a=(0.3, 0.5, 1.0), dtype=dt), True),
    ("Chiang R", lambda dt: hs.Chiang(lobes="R", dtype=dt), True),
    ("DeonFarField", lambda dt: hs.DeonFarField(sigma_a=(0.3, 0.5, 1.0), dtype=dt), False),
    ("Tabulated", lambda dt: hs.Tabulated(preset="coarse", dtype=dt), False),
    ("Marschner", lambda dt: hs.Marschner(dtype=dt), False),
    ("Huang", lambda dt: hs.Huang(tt_points=16, offset_nodes=16, dtype=dt), False),
]


@pytest.mark.parametrize("name,make,near", ALL_MODELS, ids=[m[0] for m in ALL_MODELS])
@pytest.mark.parametrize("dt", [np.float32, np.float64])
def test_every_model_returns_the_shapes_and_dtype_asked_for(name, make, near, dt):
    model = make(dt)
    assert model.dtype == np.dtype(dt) and model.near_field == near
    n = 17
    wo, wi = directions(n), directions(n)
    h = RNG.uniform(-1, 1, n) if near else None
    f = model.eval(wo, wi, h)
    assert f.shape == (n, 3) and f.dtype == dt and np.all(np.isfinite(f)) and np.all(f >= 0)
    assert model.pdf(wo, wi, h).shape == (n,)
    s = model.sample(wo, RNG.random((n, 4)), h)
    assert s.wi.shape == (n, 3) and s.weight.shape == (n, 3) and s.pdf.shape == (n,) and s.lobe.shape == (n,)
    assert np.all(s.pdf > 0) and set(s.lobe) <= {0, 1, 2, 3}
    # A sample's pdf is pdf(wo, wi) at its own wi, its weight eval / pdf (the contract).
    np.testing.assert_allclose(model.pdf(wo, s.wi, h), s.pdf, rtol=2e-3 if dt == np.float32 else 1e-9)
    np.testing.assert_allclose(model.eval(wo, s.wi, h) / s.pdf[:, None], s.weight, rtol=2e-3 if dt == np.float32 else 1e-9)
    assert model.albedo(wo, h).shape == (n, 3)
    # A shared wo (3,) broadcasts against N wi; so does a scalar h.
    one = model.eval(wo[0], wi, h[0] if near else None)
    np.testing.assert_array_equal(one[3], model.eval(wo[0], wi[3], h[0] if near else None))


def test_validation_errors_carry_the_cpp_message():
    with pytest.raises(ValueError) as e:
        hs.Chiang(eta=0.9, beta_n=0.0, sigma_a=(0, -1, 0))
    assert str(e.value) == (
        "hairscatter: invalid fiber parameters: eta = 0.9 is outside its range (1, inf) (finite); "
        "beta_n = 0 is outside its range [1e-3, 1]; sigma_a.g = -1 is outside its range [0, inf) (finite)"
    )
    with pytest.raises(ValueError, match=r"^hairscatter: DeonFarFieldMaterial: nodes = 300 is outside its range \[1, 256\]"):
        hs.DeonFarField(nodes=300)
    with pytest.raises(ValueError, match=r"^hairscatter: invalid Marschner parameters: beta_r = 2 is outside its range"):
        hs.Marschner(beta_r=2.0)
    with pytest.raises(ValueError, match=r"^hairscatter: invalid Huang parameters: aspect_ratio = 0.2 is outside its range \[0.5, 1\]$"):
        hs.Huang(aspect_ratio=0.2)
    with pytest.raises(ValueError, match="HuangMaterial: alpha_override = 1 is not supported"):
        hs.Huang(controls=hs.LobeControls(alpha_r=0.01))
    with pytest.raises(ValueError, match="Marschner et al. 2003 has no residual lobe"):
        hs.Marschner(controls=hs.LobeControls(gain_residual=0.5))
    with pytest.raises(ValueError, match=r"^hairscatter: invalid lobe controls: gain_tt = -1 is outside its range \[0, 1e6\]$"):
        hs.Chiang(controls=hs.LobeControls(gain_tt=-1.0))
    assert hs.LobeControls(tint_r=(1, 2, 2e6)).validate() == "tint_r.b = 2e+06 is outside its range [0, 1e6]"
    with pytest.raises(ValueError, match="colour channel 1 = 0.000000 is outside"):
        hs.sigma_a_from_color((0.5, 0.0, 0.5))
    with pytest.raises(ValueError, match="^hairscatter: invalid hair pigments: melanin = 1.5 is outside its range"):
        hs.sigma_a_from_pigments(melanin=1.5)
    with pytest.raises(ValueError, match="^hairscatter: invalid strand variation: redness = "):
        hs.StrandVariation(redness=(0.5, 0.2))
    with pytest.raises(ValueError, match="^hairscatter: invalid fiber parameters: beta_m = 0 is outside"):
        hs.Tabulated(beta_m=0.0)
    with pytest.raises(ValueError, match="lobes: unknown lobe 'trrt'"):
        hs.Chiang(lobes="R+TRRT")
    with pytest.raises(ValueError, match="dtype: int32 is neither float32 nor float64"):
        hs.Chiang(dtype="int32")
    with pytest.raises(TypeError, match="unknown keyword 'gain_x'"):
        hs.LobeControls(gain_x=1.0)
    with pytest.raises(TypeError):
        hs.Chiang(0.5)  # keywords only


def test_bad_arrays_raise_value_errors_naming_the_argument():
    m = hs.Chiang()
    wo, wi = directions(4), directions(4)
    with pytest.raises(ValueError, match=r"^wi: expected shape \(3,\) or \(N, 3\), got \(4, 2\)$"):
        m.eval(wo, wi[:, :2], 0.0)
    with pytest.raises(ValueError, match=r"^wi: 3 rows, but wo has 4$"):
        m.eval(wo, wi[:3], 0.0)
    with pytest.raises(ValueError, match=r"^h: 5 rows, but wo has 4$"):
        m.pdf(wo, wi, np.zeros(5))
    with pytest.raises(ValueError, match=r"^h: expected shape \(\) or \(N,\), got \(4, 1\)$"):
        m.pdf(wo, wi, np.zeros((4, 1)))
    with pytest.raises(ValueError, match="^h: this near-field model needs the offsets h"):
        m.eval(wo, wi)
    with pytest.raises(ValueError, match="^h: this far-field model integrates over h"):
        hs.DeonFarField().eval(wo, wi, 0.5)
    with pytest.raises(ValueError, match="^wo: expected real numbers, got dtype <U1"):
        m.eval(np.array(["a", "b", "c"]), wi, 0.0)
    with pytest.raises(ValueError, match="^u: expected real numbers, got dtype complex128"):
        m.sample(wo, np.zeros((4, 4), dtype=complex), 0.0)
    with pytest.raises(ValueError, match="^wo: expected real numbers, got dtype object"):
        m.albedo([object(), 1, 2], 0.0)
    with pytest.raises(ValueError, match="^wo: expected numbers, got None"):
        m.eval(None, wi, 0.0)
    with pytest.raises(ValueError, match=r"^u: expected shape \(4,\) or \(N, 4\), got \(4, 3\)$"):
        m.sample(wo, np.zeros((4, 3)), 0.0)


def test_non_contiguous_integer_and_other_dtype_inputs_give_the_same_values():
    m = hs.Chiang(sigma_a=(0.2, 0.4, 0.8))
    wo, wi, h = directions(6), directions(6), RNG.uniform(-1, 1, 6)
    want = m.eval(wo, wi, h)
    big = np.zeros((6, 7))
    big[:, 1:7:2] = wi
    assert not big[:, 1:7:2].flags.c_contiguous
    np.testing.assert_array_equal(m.eval(wo, big[:, 1:7:2], h), want)
    np.testing.assert_array_equal(m.eval(np.asfortranarray(wo), wi, h[::-1].copy()[::-1]), want)
    np.testing.assert_array_equal(m.eval([[0, 1, 0]], [[0, 1, 0]], [0]), m.eval(np.array([[0.0, 1, 0]]), [[0.0, 1, 0]], 0.0))
    # float32 input to a float64 model is widened; the result has the model's dtype.
    m32 = hs.Chiang(sigma_a=(0.2, 0.4, 0.8), dtype=np.float32)
    assert m32.eval(wo, wi, h).dtype == np.float32
    np.testing.assert_array_equal(m32.eval(wo, wi, h), m32.eval(wo.astype(np.float32), wi.astype(np.float32), h.astype(np.float32)))
    np.testing.assert_allclose(m32.eval(wo, wi, h), want, rtol=5e-4, atol=1e-7)
    # Empty batches are fine.
    assert m.eval(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0)).shape == (0, 3)


def test_non_finite_entries_give_the_contracts_zeros():
    for m, h in [(hs.Chiang(), 0.3), (hs.DeonFarField(), None), (hs.Marschner(), None)]:
        wo = directions(4)
        wi = directions(4)
        wi[1, 0] = np.nan
        wo[2, 2] = np.inf
        f = m.eval(wo, wi, h)
        assert np.all(f[1:3] == 0) and np.all(f[[0, 3]] > 0)
        pdf = m.pdf(wo, wi, h)
        assert np.all(pdf[1:3] == 0) and np.all(pdf[[0, 3]] > 0)
        u = RNG.random((4, 4))
        u[0, 3] = np.nan
        s = m.sample(wo, u, h)
        assert s.pdf[0] == 0 and s.lobe[0] == 8 and np.all(s.wi[0] == 0) and s.pdf[3] > 0


def test_a_non_finite_offset_or_outgoing_direction_gives_zeros_everywhere():
    m = hs.Chiang(sigma_a=(0.5, 0.8, 1.2))
    wo, wi = directions(4), directions(4)
    h = np.array([0.2, np.nan, -np.inf, 0.7])
    f, pdf = m.eval(wo, wi, h), m.pdf(wo, wi, h)
    assert np.all(f[1:3] == 0) and np.all(pdf[1:3] == 0) and np.all(f[[0, 3]] > 0)
    s = m.sample(wo, RNG.random((4, 4)), h)
    assert np.all(s.pdf[1:3] == 0) and np.all(s.lobe[1:3] == 8) and np.all(s.pdf[[0, 3]] > 0)
    assert np.all(m.albedo(wo, h)[1:3] == 0) and np.all(m.albedo(wo, h)[[0, 3]] > 0)
    a, backward = m.lobe_split(wo, h)
    assert np.all(a[1:3] == 0) and np.all(backward[1:3] == 0.5) and np.all(a[[0, 3]].sum(axis=1) > 0)
    d = hs.DualScatteringBcsdf(m, m.dual_tables(theta_samples=16, psi_samples=9, h_nodes=8))
    assert np.all(d.eval(wo, wi, h)[1:3] == 0) and np.all(d.pdf(wo, wi, h)[1:3] == 0)
    assert np.all(d.sample(wo, RNG.random((4, 4)), h).pdf[1:3] == 0)
    # albedo and lobe_split of a NaN, infinite or zero wo: no energy, each half 1/2, as in C++.
    for model, hh in [(m, 0.3), (hs.DeonFarField(sigma_a=(1, 1, 1)), None), (hs.Tabulated(preset="coarse", sigma_a=(1, 1, 1)), None)]:
        bad = np.array([[np.nan, 1, 0], [0, 0, 0], [np.inf, 0, 1], [0, 1, 0]])
        alb = model.albedo(bad, hh)
        assert np.all(alb[:3] == 0) and np.all(alb[3] > 0)
        a, backward = model.lobe_split(bad, hh)
        assert np.all(a[:3] == 0) and np.all(backward[:3] == 0.5)
        assert np.all(model.lobe_split([0, 1, 0], hh, centre=np.nan)[1] == 0.5)


def test_lobe_subsets_and_lobe_split_add_up():
    wo, h = directions(5), RNG.uniform(-1, 1, 5)
    wi = directions(5)
    parts = sum(hs.Chiang(sigma_a=(0.1, 0.2, 0.4), lobes=p).eval(wo, wi, h) for p in ("R", "TT", "TRT", "residual"))
    np.testing.assert_allclose(parts, hs.Chiang(sigma_a=(0.1, 0.2, 0.4)).eval(wo, wi, h), rtol=1e-12)
    m = hs.Chiang(sigma_a=(0.1, 0.2, 0.4))
    a, backward = m.lobe_split(wo, h)
    assert a.shape == (5, 4, 3) and backward.shape == (5, 4)
    np.testing.assert_allclose(a.sum(axis=1), m.albedo(wo, h), rtol=1e-12)
    assert np.all((backward >= 0) & (backward <= 1))
    # A kept subset: the dropped lobes split nothing.
    a_r, _ = hs.Chiang(lobes=["R", "TRT"]).lobe_split(wo, h)
    assert np.all(a_r[:, [1, 3]] == 0) and np.all(a_r[:, [0, 2]] > 0)
    # Lossless: the furnace is 1.
    np.testing.assert_allclose(hs.Chiang().albedo(wo, h), 1.0, rtol=1e-12)
    np.testing.assert_allclose(hs.DeonFarField().albedo(wo), 1.0, rtol=1e-12)


def test_controls_scale_the_albedo_as_documented():
    wo, h = directions(3), RNG.uniform(-1, 1, 3)
    plain = hs.Chiang(sigma_a=(0.2, 0.3, 0.5))
    a, _ = plain.lobe_split(wo, h)
    c = hs.LobeControls(gain_r=2.0, gain_trt=0.3, tint_tt=(1.0, 0.55, 0.3), gain_residual=0.0)
    assert c.gain == (2.0, 1.0, 0.3, 0.0) and c.alpha == (None, None, None)
    tinted = hs.Chiang(sigma_a=(0.2, 0.3, 0.5), controls=c)
    want = 2 * a[:, 0] + a[:, 1] * np.array([1.0, 0.55, 0.3]) + 0.3 * a[:, 2]
    np.testing.assert_allclose(tinted.albedo(wo, h), want, rtol=1e-12)
    assert hs.LobeControls(alpha_tt=0.05).alpha == (None, 0.05, None)


def test_former_pigment_names_give_the_same_values():
    for ce, cp in ((1.3, 0.0), (0.4, 0.7), (0.0, 2.0)):
        assert np.array_equal(hs.sigma_a_from_melanin(ce, cp), hs.sigma_a_from_concentrations(ce, cp))
    for m, r in ((0.0, 0.0), (0.6, 0.25), (1.0, 1.0)):
        assert np.array_equal(hs.sigma_a_from_melanin_redness(m, r), hs.sigma_a_from_melanin_amount(m, r))


def test_pigments_follow_the_documented_formulas():
    np.testing.assert_allclose(hs.sigma_a_from_concentrations(1.0, 0.0), [0.419, 0.697, 1.37])
    np.testing.assert_allclose(hs.sigma_a_from_concentrations(0.0, 2.0), [0.374, 0.8, 2.1])
    c = -math.log(1 - 0.6)
    eu, pheo = hs.melanin_concentrations(0.6, 0.25)
    assert eu == pytest.approx(0.75 * c, rel=1e-15) and pheo == pytest.approx(0.25 * c, rel=1e-15)
    np.testing.assert_allclose(hs.sigma_a_from_melanin_amount(0.6, 0.25), hs.sigma_a_from_concentrations(eu, pheo), rtol=1e-15)
    assert hs.melanin_concentrations(1.0)[0] == pytest.approx(math.log(1e4))
    b = 0.3
    d = 5.969 - 0.215 * b + 2.532 * b**2 - 10.73 * b**3 + 5.574 * b**4 + 0.245 * b**5
    np.testing.assert_allclose(hs.sigma_a_from_color((0.5, 0.25, 1.0), b), [(math.log(x) / d) ** 2 for x in (0.5, 0.25, 1.0)], rtol=1e-12)
    np.testing.assert_allclose(hs.sigma_a_from_dye((0.5, 0.25, 1.0), b), hs.sigma_a_from_color((0.5, 0.25, 1.0), b), rtol=1e-15)
    np.testing.assert_allclose(
        hs.sigma_a_from_pigments(0.6, 0.25, (0.5, 0.25, 1.0), b),
        hs.sigma_a_from_melanin_amount(0.6, 0.25) + hs.sigma_a_from_dye((0.5, 0.25, 1.0), b),
        rtol=1e-15,
    )


def test_strand_variation_draws_within_its_intervals_and_feeds_a_model():
    v = hs.StrandVariation(seed=3, melanin=(0.2, 0.7), redness=(0.1, 0.3), roughness_scale=(0.5, 2.0))
    draws = [v.at(s) for s in range(200)]
    assert all(0.2 <= d["melanin"] <= 0.7 and 0.1 <= d["redness"] <= 0.3 for d in draws)
    assert draws[5] == v.at(5) and draws[5] != draws[6]
    p = v.params(5, beta_m=0.3, beta_n=0.3)
    assert p["beta_m"] == pytest.approx(0.3 * draws[5]["roughness_scale"])
    np.testing.assert_allclose(p["sigma_a"], hs.sigma_a_from_melanin_amount(draws[5]["melanin"], draws[5]["redness"]))
    assert hs.Chiang(**p).eval([0, 1, 0], [0, 1, 0], 0.0).shape == (3,)


def test_frames_put_wo_in_the_xz_plane_and_round_trip():
    t = np.array([0.0, 1.0, 0.2])
    wo = np.array([0.3, 0.2, 1.0])
    f = hs.FiberFrame(t, wo)
    np.testing.assert_allclose(f.x, t / np.linalg.norm(t))
    local = f.to_local(wo / np.linalg.norm(wo))
    assert abs(local[1]) < 1e-15 and local[2] > 0
    w = directions(8)
    np.testing.assert_allclose(f.to_world(f.to_local(w)), w, atol=1e-15)
    back = hs.FiberFrame.facing(t, -wo, wo)
    np.testing.assert_allclose(back.z, f.z, atol=1e-15)
    theta, phi = hs.angles(hs.direction(0.4, -2.0))
    assert theta == pytest.approx(0.4) and phi == pytest.approx(-2.0)


def test_dual_tables_build_save_load_and_drive_the_bcsdf(tmp_path):
    m = hs.DeonFarField(sigma_a=hs.sigma_a_from_melanin_amount(0.3, 0.1))
    t = m.dual_tables(theta_samples=16, psi_samples=9)
    assert (t.size, t.psi_samples, t.lobes, t.formulation) == (16, 9, 4, "improved")
    arr = t.arrays()
    assert arr["theta"].shape == (16,) and arr["window"].shape == (16, 4, 9, 3) and arr["psi"][-1] == pytest.approx(math.pi)
    assert np.all((arr["a_f"] > 0) & (arr["a_f"] + arr["a_b"] <= 1 + 1e-9))
    # a_b and a_f are π W(0) and π W(π) summed over the lobes.
    np.testing.assert_allclose(arr["a_b"], math.pi * arr["window"][:, :, 0].sum(axis=1), rtol=1e-12)
    np.testing.assert_allclose(arr["a_f"], math.pi * arr["window"][:, :, -1].sum(axis=1), rtol=1e-12)
    at = t.lookup(arr["theta"][3])
    np.testing.assert_allclose(at["a_f"], arr["a_f"][3], rtol=1e-12)
    path = tmp_path / "tables.hsdt"
    t.save(str(path))
    loaded = hs.DualTables.load(str(path))
    for k, v in arr.items():
        np.testing.assert_array_equal(loaded.arrays()[k], v)
    path.write_bytes(path.read_bytes()[:-3])
    with pytest.raises(RuntimeError, match="is not a valid dual-scattering table file: size"):
        hs.DualTables.load(str(path))
    with pytest.raises(RuntimeError, match="cannot open dual-scattering tables"):
        hs.DualTables.load(str(tmp_path / "missing"))
    t.save(str(tmp_path / "again.hsdt"))
    as_float = hs.DualTables.load(str(tmp_path / "again.hsdt"), dtype="float32")
    assert as_float.dtype == np.float32
    np.testing.assert_allclose(as_float.arrays()["a_f"], arr["a_f"], rtol=1e-6)

    d = hs.DualScatteringBcsdf(m, loaded)
    wo, wi = directions(50), directions(50)
    lit = d.eval(wo, wi, direct_fraction=1.0, n=0.0)
    shadowed = d.eval(wo, wi, direct_fraction=0.0, n=3.0)
    assert lit.shape == (50, 3) and np.all(lit >= 0) and np.all(np.isfinite(shadowed))
    # Fully lit with no hair around, the dual BCSDF adds the local backscattering to f.
    assert np.all(lit.sum(axis=1) >= m.eval(wo, wi).sum(axis=1) - 1e-12)
    s = d.sample(wo, RNG.random((50, 4)), n=2.0, direct_fraction=0.0)
    ok = s.pdf > 0
    np.testing.assert_allclose(d.pdf(wo[ok], s.wi[ok]), s.pdf[ok], rtol=1e-9)
    np.testing.assert_allclose(s.weight[ok], s.f[ok] / s.pdf[ok, None], rtol=1e-12)
    assert set(s.component) <= set(range(5))
    # Tables of any model drive a BCSDF over any other of the same dtype (Marschner has none of its own).
    with pytest.raises(TypeError, match="lobe_split"):
        hs.Marschner().dual_tables()
    assert hs.DualScatteringBcsdf(hs.Marschner(), t).eval(wo[0], wi[0]).shape == (3,)
    with pytest.raises(ValueError, match="tables: their dtype differs"):
        hs.DualScatteringBcsdf(hs.Chiang(dtype="float32"), t)
    with pytest.raises(TypeError, match="Chiang lobe subset"):
        hs.DualScatteringBcsdf(hs.Chiang(lobes="primary"), t)
    near = hs.Chiang()
    nd = hs.DualScatteringBcsdf(near, near.dual_tables(theta_samples=16, psi_samples=9, h_nodes=8, formulation="zinke2008"))
    assert nd.eval(wo, wi, RNG.uniform(-1, 1, 50)).shape == (50, 3)


def test_a_long_call_releases_the_gil():
    """Another Python thread runs while eval's C++ loop does: the main thread makes progress
    in the middle of the call (impossible if the call held the GIL)."""
    import threading
    import time

    m = hs.Chiang(sigma_a=(0.2, 0.4, 0.8))
    n = 1_000_000
    wo, wi, h = directions(n), directions(n), RNG.uniform(-1, 1, n)
    span, ticks = {}, []

    def call():
        span["enter"] = time.perf_counter()
        m.eval(wo, wi, h)
        span["exit"] = time.perf_counter()

    t = threading.Thread(target=call)
    t.start()
    while t.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(1e-4)  # a few thousand ticks a second, not millions (sleep keeps the GIL free too)
    t.join()
    d = span["exit"] - span["enter"]
    middle = [x for x in ticks if span["enter"] + 0.3 * d < x < span["exit"] - 0.3 * d]
    assert d > 0.01 and middle, f"no progress of the main thread during the {1e3 * d:.0f} ms call"
