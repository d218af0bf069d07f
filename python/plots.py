#!/usr/bin/env python3
"""Plots of hairscatter's models with matplotlib (Agg: no display needed), written as PNG.

    python3 python/plots.py [--out DIR] [--quick] [--only NAME[,NAME...]]

Figures (NAME.png in DIR, default build/plots):
  longitudinal  M_p over θi per lobe (Chiang et al. 2016's fiber, h-averaged), at three θo
  azimuthal     N_p over φ per lobe as polar plots, Marschner et al. 2003 Fig. 5-style:
                Marschner's model and d'Eon's far field, θo = 0, blond hair
  sphere        a far-field lobe on the sphere: f(wo, ·) of the far-field fiber, θo = 30°
  swatches      colour swatches over melanin amount and redness: the far-field fiber's
                albedo at θo = 0, gamma-encoded
  dual          the dual-scattering tables' a_f and a_b over θ for five melanin amounts

--quick uses coarse grids (the test suite runs it so); the module must be importable
(scripts/python.sh builds it; PYTHONPATH=build/python/python).
"""

import argparse
import math
import os
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import hairscatter as hs  # noqa: E402

LOBES = ("R", "TT", "TRT", "residual")
COLOURS = {"R": "tab:blue", "TT": "tab:red", "TRT": "tab:green", "residual": "tab:gray"}
BLOND = hs.sigma_a_from_melanin_amount(0.3, 0.2)


def gauss_legendre(a, b, n):
    x, w = np.polynomial.legendre.leggauss(n)
    return a + (b - a) * (x + 1) / 2, w * (b - a) / 2


def longitudinal(out, quick):
    """M_p(θi) of each lobe: ∫ f_p cosθi dφ over φ and h, divided by the lobe's A_p."""
    n_theta, n_phi, n_h = (61, 32, 8) if quick else (241, 96, 24)
    theta_i = np.linspace(-math.pi / 2, math.pi / 2, n_theta)
    phi, w_phi = gauss_legendre(-math.pi, math.pi, n_phi)
    gamma, w_gamma = gauss_legendre(-math.pi / 2, math.pi / 2, n_h)
    h, w_h = np.sin(gamma), w_gamma * np.cos(gamma) / 2  # ½∫ dh in γ = asin h
    fig, axes = plt.subplots(1, 3, figsize=(10, 3.2), sharey=True)
    for ax, theta_o_deg in zip(axes, (0, 30, 60)):
        wo = hs.direction(math.radians(theta_o_deg), 0.0)
        T, P, H = np.meshgrid(theta_i, phi, h, indexing="ij")
        wi = hs.direction(T.ravel(), P.ravel())
        for lobe in LOBES:
            model = hs.Chiang(sigma_a=BLOND, lobes=lobe)
            f = model.eval(wo, wi, H.ravel()).mean(axis=1).reshape(T.shape)
            density = np.einsum("ijk,j,k->i", f, w_phi, w_h) * np.cos(theta_i)
            a = model.albedo(wo, h).mean(axis=1) @ w_h
            ax.plot(np.degrees(theta_i), density / a, color=COLOURS[lobe], label=lobe)
        ax.axvline(-theta_o_deg, color="k", lw=0.5, ls=":")
        ax.set_title(f"θo = {theta_o_deg}°")
        ax.set_xlabel("θi (degrees)")
        ax.set_xlim(-90, 90)
    axes[0].set_ylabel("M_p(θi) per radian")
    axes[0].legend(frameon=False)
    fig.suptitle("Longitudinal lobes of Chiang et al. 2016 (βm = 0.3, α = 2°, h-averaged)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "longitudinal.png", dpi=80)
    plt.close(fig)


def azimuthal_lobes(model_of, wo, phi, n_theta):
    """Per lobe, N_p(φ) A_p = ∫ f_p cosθi dθi (channel mean): model_of(gains) with only that lobe's gain 1."""
    theta, w_theta = gauss_legendre(-math.pi / 2, math.pi / 2, n_theta)
    T, P = np.meshgrid(theta, phi, indexing="ij")
    wi = hs.direction(T.ravel(), P.ravel())
    curves = {}
    for p, lobe in enumerate(LOBES[:3]):
        gains = {f"gain_{name.lower()}": float(q == p) for q, name in enumerate(LOBES[:3])}
        f = model_of(gains).eval(wo, wi).mean(axis=1).reshape(T.shape)
        curves[lobe] = (f * (w_theta * np.cos(theta))[:, None]).sum(axis=0)
    return curves


def azimuthal(out, quick):
    n_phi, n_theta = (181, 24) if quick else (721, 96)
    phi = np.linspace(-math.pi, math.pi, n_phi)
    wo = hs.direction(0.0, 0.0)
    models = {
        "Marschner 2003": lambda g: hs.Marschner(
            sigma_a=BLOND, controls=hs.LobeControls(**g), beta_n=0.15, beta_r=math.radians(5)
        ),
        "d'Eon 2011 far field": lambda g: hs.DeonFarField(
            sigma_a=BLOND, controls=hs.LobeControls(gain_residual=0.0, **g), beta_n=0.15, beta_m=0.2
        ),
    }
    curves = {name: azimuthal_lobes(make, wo, phi, n_theta) for name, make in models.items()}
    fig, axes = plt.subplots(1, 3, figsize=(9, 3.4), subplot_kw={"projection": "polar"})
    for ax, lobe in zip(axes, LOBES[:3]):
        for (name, c), ls in zip(curves.items(), ("-", "--")):
            ax.plot(phi, c[lobe], ls, color=COLOURS[lobe], lw=1.2, label=name)
        ax.set_title(f"N_{lobe}(φ)", fontsize=10)
        ax.set_theta_zero_location("E")
        ax.tick_params(labelsize=7)
        ax.set_yticklabels([])
    axes[0].legend(loc="lower left", bbox_to_anchor=(-0.25, -0.28), fontsize=7, frameon=False)
    fig.suptitle("Azimuthal scattering per lobe at θo = 0 (blond, βn = 0.15; φ = 0 backward)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "azimuthal.png", dpi=80, bbox_inches="tight")
    plt.close(fig)


def sphere(out, quick):
    n = 60 if quick else 160
    theta = np.linspace(-math.pi / 2, math.pi / 2, n)
    phi = np.linspace(-math.pi, math.pi, 2 * n)
    T, P = np.meshgrid(theta, phi, indexing="ij")
    wi = hs.direction(T, P)
    wo = hs.direction(math.radians(30), 0.0)
    model = hs.DeonFarField(sigma_a=BLOND, beta_m=0.25, beta_n=0.3)
    # f without the cosine (the BCSDF), radius its cube root: TT and TRT stay visible next to
    # R. The cosine is floored near the poles, where both vanish.
    f = model.eval(wo, wi.reshape(-1, 3)).mean(axis=1).reshape(T.shape) / np.maximum(np.cos(T), 0.05)
    r = f ** (1 / 3)
    xyz = wi * r[..., None]
    colours = plt.cm.viridis(r / r.max())
    fig = plt.figure(figsize=(4.5, 4.5))
    ax = fig.add_subplot(projection="3d")
    # Plot axes: x = the fiber tangent drawn vertical.
    ax.plot_surface(xyz[..., 1], xyz[..., 2], xyz[..., 0], facecolors=colours, rstride=1, cstride=1, linewidth=0)
    ax.plot([0, 0], [0, 0], [-1.1 * r.max(), 1.1 * r.max()], color="k", lw=1)
    ax.quiver(0, 0, 0, wo[1], wo[2], wo[0], length=r.max(), color="tab:blue")
    ax.set_box_aspect((1, 1, 1))
    ax.set_axis_off()
    ax.view_init(elev=15, azim=-60)
    ax.set_title("Far-field lobe, radius (f / cosθi)^(1/3)\nθo = 30° (blue: wo), fiber axis vertical", fontsize=9)
    fig.savefig(out / "sphere.png", dpi=80, bbox_inches="tight")
    plt.close(fig)


def swatches(out, quick):
    melanin = np.linspace(0.0, 1.0, 6 if quick else 11)
    redness = np.linspace(0.0, 1.0, 4 if quick else 6)
    wo = hs.direction(0.0, 0.0)
    rgb = np.zeros((len(redness), len(melanin), 3))
    for i, r in enumerate(redness):
        for j, m in enumerate(melanin):
            model = hs.DeonFarField(sigma_a=hs.sigma_a_from_melanin_amount(m, r), nodes=16 if quick else 0)
            rgb[i, j] = model.albedo(wo)
    fig, ax = plt.subplots(figsize=(6, 3))
    ax.imshow(np.clip(rgb, 0, 1) ** (1 / 2.2), origin="lower", aspect="auto",
              extent=(melanin[0] - 0.05, melanin[-1] + 0.05, redness[0] - 0.1, redness[-1] + 0.1))
    ax.set_xlabel("melanin amount")
    ax.set_ylabel("redness")
    ax.set_title("Single-scattering albedo at θo = 0 (far field, gamma 2.2)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "swatches.png", dpi=80)
    plt.close(fig)


def dual(out, quick):
    fig, ax = plt.subplots(figsize=(6, 3.4))
    samples = 16 if quick else 64
    for m, colour in zip((0.1, 0.25, 0.4, 0.6, 0.8), plt.cm.copper(np.linspace(0.9, 0.1, 5))):
        model = hs.DeonFarField(sigma_a=hs.sigma_a_from_melanin_amount(m, 0.1))
        t = model.dual_tables(theta_samples=samples, psi_samples=9 if quick else 33).arrays()
        theta = np.degrees(t["theta"])
        ax.plot(theta, t["a_f"].mean(axis=1), color=colour, label=f"m = {m}")
        ax.plot(theta, t["a_b"].mean(axis=1), "--", color=colour)
    ax.set_xlabel("θ (degrees)")
    ax.set_ylabel("albedo (channel mean)")
    ax.set_title("Dual scattering: a_f (solid) and a_b (dashed), redness 0.1", fontsize=10)
    ax.legend(frameon=False, fontsize=8, ncol=5, loc="upper center", bbox_to_anchor=(0.5, -0.2))
    fig.tight_layout()
    fig.savefig(out / "dual.png", dpi=80)
    plt.close(fig)


FIGURES = {"longitudinal": longitudinal, "azimuthal": azimuthal, "sphere": sphere, "swatches": swatches, "dual": dual}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join("build", "plots"), help="output directory (default build/plots)")
    parser.add_argument("--quick", action="store_true", help="coarse grids (seconds)")
    parser.add_argument("--only", default=",".join(FIGURES), help="comma-separated figure names")
    args = parser.parse_args(argv)
    names = [n for n in args.only.split(",") if n]
    unknown = [n for n in names if n not in FIGURES]
    if unknown:
        parser.error(f"unknown figure(s) {', '.join(unknown)} (figures: {', '.join(FIGURES)})")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for name in names:
        FIGURES[name](out, args.quick)
        print(out / f"{name}.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
