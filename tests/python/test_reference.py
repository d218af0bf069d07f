"""The module's values equal plain C++ calls bit for bit.

python/python_reference.cpp evaluates every model (float and double) on fixed inputs and
prints inputs and results as hexadecimal floats; each call kind is fed here to the module
in one vectorised call, and row by row, and every bit must agree.
"""

import collections
import subprocess

import numpy as np
import pytest

import hairscatter as hs

SIGMA_A = (0.6, 0.9, 1.6)
ALPHA = 0.035

# The cases of python_reference.cpp, with the same parameters.
CASES = {
    "chiang": lambda dt: hs.Chiang(eta=1.55, beta_m=0.3, beta_n=0.25, alpha=ALPHA, sigma_a=SIGMA_A, dtype=dt),
    "chiang_r_tt": lambda dt: hs.Chiang(
        eta=1.55, beta_m=0.3, beta_n=0.25, alpha=ALPHA, sigma_a=SIGMA_A, lobes="R+TT", dtype=dt
    ),
    "deon": lambda dt: hs.DeonFarField(
        eta=1.55,
        beta_m=0.35,
        beta_n=0.3,
        alpha=ALPHA,
        sigma_a=SIGMA_A,
        controls=hs.LobeControls(gain_r=2.0, tint_tt=(1.0, 0.55, 0.3), alpha_trt=0.05),
        dtype=dt,
    ),
    "tabulated": lambda dt: hs.Tabulated(
        eta=1.55, beta_m=0.3, beta_n=0.3, alpha=ALPHA, sigma_a=SIGMA_A, preset="coarse", dtype=dt
    ),
    "marschner": lambda dt: hs.Marschner(
        eta=1.55,
        sigma_a=SIGMA_A,
        alpha_r=-0.12,
        beta_r=0.13,
        beta_n=0.3,
        eccentricity=0.9,
        caustic_width=0.26,
        caustic_gain=0.5,
        caustic_fade=0.3,
        caustic_dh_max=0.5,
        dtype=dt,
    ),
    "huang": lambda dt: hs.Huang(
        eta=1.55,
        roughness=0.3,
        alpha=ALPHA,
        sigma_a=SIGMA_A,
        aspect_ratio=0.7,
        orientation=0.4,
        offset_nodes=16,
        tt_points=32,
        trt_per_tt=2,
        dtype=dt,
    ),
}
DTYPES = {"_f32": np.float32, "_f64": np.float64}
# The dual BCSDF's tables and light state in python_reference.cpp.
TABLES = dict(theta_samples=16, psi_samples=9, h_nodes=8)
LIGHT = dict(direct_fraction=0.25, n=2.0, beyond=3.0)


@pytest.fixture(scope="module")
def reference(reference_program):
    out = subprocess.run([reference_program], check=True, capture_output=True, text=True).stdout
    rows = collections.defaultdict(list)
    for line in out.splitlines():
        name, call, *values = line.split()
        rows[name, call].append([float.fromhex(v) for v in values])
    return {key: np.array(v) for key, v in rows.items()}


def same_bits(got, want, dtype):
    got = np.ascontiguousarray(np.asarray(got, dtype=dtype))
    want = np.ascontiguousarray(np.asarray(want).astype(dtype))
    assert got.shape == want.shape
    bits = np.uint32 if dtype == np.float32 else np.uint64
    differ = np.nonzero(got.view(bits).ravel() != want.view(bits).ravel())[0]
    assert differ.size == 0, f"{differ.size} values differ, first at {differ[0]}: {got.ravel()[differ[0]]!r} != {want.ravel()[differ[0]]!r}"


def case_params():
    return [(name, suffix) for name in CASES for suffix in DTYPES]


@pytest.mark.parametrize("name,suffix", case_params())
def test_every_call_equals_the_cpp_loop_bit_for_bit(reference, name, suffix):
    dt = DTYPES[suffix]
    model = CASES[name](dt)
    key = name + suffix
    take_h = model.near_field

    def h_of(col):
        return col.astype(dt) if take_h else None

    e = reference[key, "eval"]
    wo, wi, h = e[:, 0:3].astype(dt), e[:, 3:6].astype(dt), e[:, 6]
    same_bits(model.eval(wo, wi, h_of(h)), e[:, 7:10], dt)
    same_bits(model.pdf(wo, wi, h_of(h)), e[:, 10], dt)
    f, pdf = model.eval_pdf(wo, wi, h_of(h))
    same_bits(f, e[:, 7:10], dt)
    same_bits(pdf, e[:, 10], dt)
    # The contract's zeros for an infinite and a zero wi (the last two rows) are among them.
    assert not np.any(e[-2:, 7:11])

    s = reference[key, "sample"]
    got = model.sample(s[:, 0:3].astype(dt), s[:, 3:7].astype(dt), h_of(s[:, 7]))
    same_bits(got.wi, s[:, 8:11], dt)
    same_bits(got.weight, s[:, 11:14], dt)
    same_bits(got.pdf, s[:, 14], dt)
    np.testing.assert_array_equal(got.lobe, s[:, 15].astype(np.int8))

    a = reference[key, "albedo"]
    same_bits(model.albedo(a[:, 0:3].astype(dt), h_of(a[:, 3])), a[:, 4:7], dt)

    if (key, "split") in reference:
        p = reference[key, "split"]
        split_a, backward = model.lobe_split(p[:, 0:3].astype(dt), h_of(p[:, 3]), p[:, 4].astype(dt))
        same_bits(split_a, p[:, 5:17].reshape(-1, 4, 3), dt)
        same_bits(backward, p[:, 17:21], dt)
    else:
        with pytest.raises(TypeError, match="lobe_split"):
            model.lobe_split(wo, h_of(h))

    if (key, "dual") in reference:
        d = reference[key, "dual"]
        bcsdf = hs.DualScatteringBcsdf(model, model.dual_tables(**TABLES))
        dwo, dwi, dh = d[:, 0:3].astype(dt), d[:, 3:6].astype(dt), h_of(d[:, 6])
        same_bits(bcsdf.eval(dwo, dwi, dh, **LIGHT), d[:, 7:10], dt)
        same_bits(bcsdf.pdf(dwo, dwi, dh), d[:, 10], dt)


@pytest.mark.parametrize("name", ["chiang", "deon", "marschner"])
def test_single_rows_equal_the_vectorised_call(reference, name):
    for suffix, dt in DTYPES.items():
        model = CASES[name](dt)
        e = reference[name + suffix, "eval"]
        wo, wi = e[:, 0:3].astype(dt), e[:, 3:6].astype(dt)
        h = e[:, 6].astype(dt) if model.near_field else None
        batch_f, batch_pdf = model.eval(wo, wi, h), model.pdf(wo, wi, h)
        for i in range(0, len(e), 5):
            hi = h[i] if model.near_field else None
            f = model.eval(wo[i], wi[i], hi)
            assert f.shape == (3,) and f.dtype == dt
            same_bits(f, batch_f[i], dt)
            pdf = model.pdf(wo[i], wi[i], hi)
            assert isinstance(pdf, float)
            same_bits(pdf, batch_pdf[i], dt)
