#!/usr/bin/env python3
"""Cross-check shadematrix's physical truth against Mitsuba 3.

Reads every cell of a run whose matrix set `[outputs] truth_scene = true` (each cell's
truth_scene/: scene.json, one PLY per object, sky.exr, fgd.exr, truth.exr), renders the same scene
in Mitsuba with the same BSDF, and Z-tests the two per pixel. Writes mitsuba_check.md into the
run folder and exits 1 when any case disagrees beyond noise.

Conventions matched (docs/references.md, "Cross-check against Mitsuba 3"):
- camera: a pinhole with the vertical field of view (`fov_axis = "y"`), rays uniformly jittered
  over each pixel (the box filter);
- units: lights in the radiometric units the truth multiplies (a point light's intensity, a
  directional light's irradiance, inverse-square falloff); no tonemapping, linear RGB;
- bounces: the truth's `bounces` continuations after the camera's hit are Mitsuba's
  `max_depth = bounces + 2` (Mitsuba counts the camera segment and the last segment to a light);
- the BSDF: the physical model itself (PhysicalBsdf below, the twin of
  src/render/truth/physical.rs): Lambert base(1 − m)/π plus GGX with Schlick's Fresnel from
  F0 = lerp(0.04, base, m), height-correlated Smith visibility and Turquin's multiple-scattering
  compensation 1 + F0(1/E − 1) from the FGD table the tool exports; two-sided, as the truth
  shades back faces with the flipped normal; sampled as the truth samples (cosine or GGX visible
  normals, Heitz 2018), which changes only the noise;
- the sky: the truth's equirect (u = atan2(x, −z)/2π + ½) rotated half a turn into Mitsuba's
  (u = atan2(x, −z)/2π) and repeated 4× per texel, so that Mitsuba's bilinear lookup reproduces
  the truth's nearest-texel lookup.
"""

import argparse
import json
import math
import pathlib
import sys
import time

import numpy as np

import drjit as dr
import mitsuba as mi

LUMA = np.array([0.2126, 0.7152, 0.0722])


def choose_variant():
    # The scalar variant would call the Python BSDF once per sample: hours, not seconds.
    for v in ("llvm_ad_rgb",):
        if v in mi.variants():
            try:
                mi.set_variant(v)
                # The LLVM variant needs libLLVM at run time; a tiny render proves it loads.
                mi.render(mi.load_dict({"type": "scene", "integrator": {"type": "path"}, "sensor": {"type": "perspective",
                          "film": {"type": "hdrfilm", "width": 2, "height": 2}}}), spp=1)
                return v
            except Exception as e:  # noqa: BLE001 - reported below
                print(f"mitsuba variant {v} unavailable: {e}", file=sys.stderr)
    raise SystemExit(
        "Mitsuba's llvm_ad_rgb variant does not run: it needs libLLVM 16 or later "
        "(Debian: apt-get install libllvm19; set DRJIT_LIBLLVM_PATH to the library)"
    )


# The variant is set before the BSDF class below, which derives from the variant's mi.BSDF.
VARIANT = choose_variant()


def read_exr(path):
    return np.array(mi.Bitmap(str(path)), dtype=np.float64)


class FgdTable:
    """src/shading/fgd.rs FgdTable::lookup: bilinear over (√NV, perceptual roughness)."""

    def __init__(self, texels):
        self.size = texels.shape[0]
        self.g = mi.TensorXf(np.ascontiguousarray(texels[:, :, 1], dtype=np.float32).ravel())

    def lookup_g(self, nv, pr):
        m = self.size - 1
        fx = dr.clip(dr.sqrt(dr.clip(nv, 0.0, 1.0)) * m, 0.0, m)
        fy = dr.clip(dr.clip(pr, 0.0, 1.0) * m, 0.0, m)
        x0 = dr.minimum(dr.floor(fx), m - 1)
        y0 = dr.minimum(dr.floor(fy), m - 1)
        tx, ty = fx - x0, fy - y0
        xi, yi = mi.UInt32(x0), mi.UInt32(y0)

        def t(x, y):
            return dr.gather(mi.Float, self.g.array, y * self.size + x)

        a = dr.lerp(t(xi, yi), t(xi + 1, yi), tx)
        b = dr.lerp(t(xi, yi + 1), t(xi + 1, yi + 1), tx)
        return dr.lerp(a, b, ty)


FGD = None


class PhysicalBsdf(mi.BSDF):
    """The truth's physical model (render::truth::physical), f·cos as Mitsuba's eval returns."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.base = mi.Color3f(props["base_r"], props["base_g"], props["base_b"])
        self.checker = mi.Color3f(props["checker_r"], props["checker_g"], props["checker_b"])
        self.cell = props["cell"]
        self.metallic = props["metallic"]
        pr = 1.0 - props["smoothness"]
        self.pr = pr
        self.alpha = max(pr * pr, 1e-4)
        # truth.wgsl / cpu.rs sampling: the GGX share and its (floored) roughness.
        self.share = min(max(0.25 + 0.5 * props["smoothness"] * (0.5 + 0.5 * self.metallic), 0.1), 0.9)
        self.sample_alpha = max(pr * pr, 1e-3)
        flags = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide \
            | mi.BSDFFlags.BackSide
        self.m_components = [flags]
        self.m_flags = flags

    def base_at(self, si):
        if self.cell <= 0.0:
            return self.base
        cx = dr.floor(si.uv.x / self.cell)
        cy = dr.floor(si.uv.y / self.cell)
        odd = dr.eq(mi.Int32(cx + cy) & 1, 1) if hasattr(dr, "eq") else ((mi.Int32(cx + cy) & 1) == 1)
        return dr.select(odd, self.checker, self.base)

    @staticmethod
    def _sided(si, wo):
        # Two-sided as the truth: a back face is shaded with the flipped normal.
        flip = si.wi.z < 0
        wi = mi.Vector3f(si.wi.x, si.wi.y, dr.select(flip, -si.wi.z, si.wi.z))
        w = mi.Vector3f(wo.x, wo.y, dr.select(flip, -wo.z, wo.z))
        return wi, w, flip

    def _response(self, si, wi, wo):
        nl, nv = wo.z, wi.z
        valid = (nl > 0) & (nv > 0)
        h = dr.normalize(wi + wo)
        base = self.base_at(si)
        a = self.alpha
        a2 = a * a
        f0 = dr.lerp(mi.Color3f(0.04), base, self.metallic)
        vh = dr.clip(dr.dot(wi, h), 0.0, 1.0)
        nh = dr.clip(h.z, 0.0, 1.0)
        x = 1.0 - vh
        fresnel = f0 + (1.0 - f0) * (x * x * x * x * x)
        d = nh * nh * (a2 - 1.0) + 1.0
        ggx = a2 / (dr.pi * d * d)
        gv = nl * dr.sqrt(nv * nv * (1.0 - a2) + a2)
        gl = nv * dr.sqrt(nl * nl * (1.0 - a2) + a2)
        vis = 0.5 / dr.maximum(gv + gl, 1e-12)
        e = dr.maximum(FGD.lookup_g(nv, self.pr), 1e-4)
        comp = 1.0 + f0 * (1.0 / e - 1.0)
        f = base * (1.0 - self.metallic) / dr.pi + fresnel * ggx * vis * comp
        return dr.select(valid, f * nl, 0.0)

    def _pdf(self, wi, wo):
        nl, nv = wo.z, wi.z
        valid = (nl > 0) & (nv > 0)
        a = self.sample_alpha
        a2 = a * a
        h = dr.normalize(wi + wo)
        d = h.z * h.z * (a2 - 1.0) + 1.0
        ggx = a2 / (dr.pi * d * d)
        g1 = 2.0 * nv / (nv + dr.sqrt(a2 + (1.0 - a2) * nv * nv))
        spec = ggx * g1 / (4.0 * nv)
        return dr.select(valid, self.share * spec + (1.0 - self.share) * nl / dr.pi, 0.0)

    def eval(self, ctx, si, wo, active=True):
        wi, w, _ = self._sided(si, wo)
        return dr.select(active, self._response(si, wi, w), 0.0)

    def pdf(self, ctx, si, wo, active=True):
        wi, w, _ = self._sided(si, wo)
        return dr.select(active, self._pdf(wi, w), 0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

    def sample(self, ctx, si, sample1, sample2, active=True):
        wi, _, flip = self._sided(si, mi.Vector3f(0, 0, 1))
        u1, u2 = sample2.x, sample2.y
        # Cosine-weighted hemisphere.
        r = dr.sqrt(u1)
        phi = 2.0 * dr.pi * u2
        cosine = mi.Vector3f(r * dr.cos(phi), r * dr.sin(phi), dr.sqrt(dr.maximum(1.0 - u1, 0.0)))
        # GGX visible normals (Heitz 2018).
        a = self.sample_alpha
        vh = dr.normalize(mi.Vector3f(a * wi.x, a * wi.y, wi.z))
        lensq = vh.x * vh.x + vh.y * vh.y
        t1 = dr.select(lensq > 0, mi.Vector3f(-vh.y, vh.x, 0.0) * dr.rsqrt(dr.maximum(lensq, 1e-30)),
                       mi.Vector3f(1.0, 0.0, 0.0))
        t2 = dr.cross(vh, t1)
        p1 = r * dr.cos(phi)
        blend = 0.5 * (1.0 + vh.z)
        p2 = (1.0 - blend) * dr.sqrt(dr.maximum(1.0 - p1 * p1, 0.0)) + blend * r * dr.sin(phi)
        n_h = p1 * t1 + p2 * t2 + dr.sqrt(dr.maximum(1.0 - p1 * p1 - p2 * p2, 0.0)) * vh
        m = dr.normalize(mi.Vector3f(a * n_h.x, a * n_h.y, dr.maximum(n_h.z, 0.0)))
        glossy = 2.0 * dr.dot(wi, m) * m - wi
        wo = dr.select(sample1 < self.share, glossy, cosine)
        pdf = self._pdf(wi, wo)
        f = self._response(si, wi, wo)
        ok = active & (pdf > 0) & (wi.z > 0)
        bs = dr.zeros(mi.BSDFSample3f)
        bs.wo = mi.Vector3f(wo.x, wo.y, dr.select(flip, -wo.z, wo.z))
        bs.pdf = dr.select(ok, pdf, 0.0)
        bs.eta = 1.0
        bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
        bs.sampled_component = 0
        return bs, dr.select(ok, f / dr.maximum(pdf, 1e-30), 0.0)

    def traverse(self, callback):
        pass

    def to_string(self):
        return "PhysicalBsdf[]"


def sky_for_mitsuba(sky):
    """The truth's equirect in Mitsuba's u origin, 4× per texel (nearest under bilinear)."""
    w = sky.shape[1]
    rolled = np.roll(sky[:, :, :3], -w // 2, axis=1)
    return np.repeat(np.repeat(rolled, 4, axis=0), 4, axis=1).astype(np.float32)


def scene_dict(folder, record):
    cam = record["camera"]
    d = {
        "type": "scene",
        "integrator": {
            "type": "path",
            # Every bounce under roulette past the budget (Mitsuba's own roulette, also unbiased).
            "max_depth": -1 if record.get("roulette") else record["bounces"] + 2,
            "rr_depth": record["bounces"] + 2 if record.get("roulette") else record["bounces"] + 3,
            "hide_emitters": not record["background"],
        },
        "sensor": {
            "type": "perspective",
            "fov": cam["fov_y_deg"],
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=cam["position"], target=cam["target"], up=cam["up"]),
            "film": {
                "type": "hdrfilm",
                "width": record["width"],
                "height": record["height"],
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
                "sample_border": False,
            },
        },
    }
    for i, light in enumerate(record["lights"]):
        if light["kind"] == "point":
            d[f"light_{i}"] = {"type": "point", "position": light["position"],
                               "intensity": {"type": "rgb", "value": light["intensity"]}}
        elif light["kind"] == "directional":
            d[f"light_{i}"] = {"type": "directional", "direction": light["direction"],
                               "irradiance": {"type": "rgb", "value": light["irradiance"]}}
        else:
            raise ValueError("a spot light: Mitsuba's spot falloff differs from the pipelines' smoothstep")
    if record["sky"]:
        sky = read_exr(folder / record["sky"])
        d["sky"] = {"type": "envmap", "bitmap": mi.Bitmap(sky_for_mitsuba(sky))}
    for obj in record["objects"]:
        if any(e > 0 for e in obj["emission"]):
            raise ValueError("an emissive object: Mitsuba's area emitters are one-sided, the truth's two-sided")
        checker = obj["checker"] or {"color": [0, 0, 0], "cell": 0.0}
        base, chk = obj["base_color"], checker["color"]
        d[obj["mesh"].replace(".", "_")] = {
            "type": "ply",
            "filename": str(folder / obj["mesh"]),
            "face_normals": False,
            "bsdf": {
                "type": "shadematrix_physical",
                "base_r": base[0], "base_g": base[1], "base_b": base[2],
                "checker_r": chk[0], "checker_g": chk[1], "checker_b": chk[2],
                "cell": checker["cell"],
                "metallic": obj["metallic"],
                "smoothness": obj["smoothness"],
            },
        }
    return d


def check_uvs(scene, folder, record):
    """The PLY's u, v reach Mitsuba unchanged (the checker depends on them)."""
    for shape in scene.shapes():
        obj = next((o for o in record["objects"] if o["mesh"].replace(".", "_") == shape.id()), None)
        if obj is None or not obj["checker"]:
            continue
        data = (folder / obj["mesh"]).read_bytes()
        body = data[data.index(b"end_header\n") + 11:]
        n = shape.vertex_count()
        ours = np.frombuffer(body[: n * 32], dtype="<f4").reshape(n, 8)[:, 6:8]
        theirs = np.array(shape.vertex_texcoords_buffer()).reshape(n, 2)
        if not np.allclose(ours, theirs, atol=1e-6):
            raise ValueError(f"{obj['mesh']}: Mitsuba read other texture coordinates than the PLY holds")


def native_paths_per_second(folder, record):
    """Mitsuba's speed with its own compiled BSDF on the same scene (`principled`, two-sided: not
    the same model, so timed only, never compared): one render of all the samples after a
    one-sample render that compiles its kernels."""
    d = scene_dict(folder, record)
    for obj in record["objects"]:
        base = obj["base_color"]
        d[obj["mesh"].replace(".", "_")]["bsdf"] = {
            "type": "twosided",
            "bsdf": {
                "type": "principled",
                "base_color": {"type": "rgb", "value": base},
                "metallic": obj["metallic"],
                "roughness": 1.0 - obj["smoothness"],
            },
        }
    scene = mi.load_dict(d)
    mi.render(scene, spp=1)
    start = time.perf_counter()
    np.array(mi.render(scene, spp=record["spp"], seed=7))
    dr.sync_thread()
    seconds = time.perf_counter() - start
    return record["width"] * record["height"] * record["spp"] / seconds


def render(scene, spp, passes):
    """Mean, and the standard error of its luminance from the spread of `passes` independent passes."""
    images = []
    for seed in range(passes):
        images.append(np.array(mi.render(scene, spp=spp // passes, seed=seed + 1), dtype=np.float64))
    stack = np.stack(images)
    mean = stack.mean(axis=0)
    lum = stack @ LUMA
    se = lum.std(axis=0, ddof=1) / math.sqrt(passes)
    return mean, se


def compare(mi_mean, mi_se, truth):
    t_lum = truth[:, :, :3] @ LUMA
    t_se = truth[:, :, 3]
    m_lum = mi_mean @ LUMA
    # A floor of 0.1 % of the value: where both are exact (a constant sky seen directly) the only
    # difference left is float rounding.
    se = np.sqrt(mi_se**2 + t_se**2 + (1e-3 * np.abs(t_lum)) ** 2)
    z = (m_lum - t_lum) / np.maximum(se, 1e-30)
    ratio = m_lum.sum() / t_lum.sum()
    ratio_se = ratio * math.sqrt((mi_se**2).sum() / m_lum.sum() ** 2 + (t_se**2).sum() / t_lum.sum() ** 2)
    z_mean = (m_lum.sum() - t_lum.sum()) / math.sqrt((mi_se**2).sum() + (t_se**2).sum())
    return {
        "ratio": ratio,
        "ratio_se": ratio_se,
        "z_mean": z_mean,
        "z_rms": float(np.sqrt((z**2).mean())),
        "beyond_5": float((np.abs(z) > 5).mean()),
        "relative_noise": float(np.sqrt((mi_se**2).mean()) / max(m_lum.mean(), 1e-30)),
        "truth_relative_noise": float(np.sqrt((t_se**2).mean()) / max(t_lum.mean(), 1e-30)),
    }


def main():
    global FGD
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run", type=pathlib.Path, help="a run folder whose cells have truth_scene/")
    ap.add_argument("--passes", type=int, default=16, help="independent Mitsuba passes for its standard error")
    args = ap.parse_args()
    variant = VARIANT
    mi.register_bsdf("shadematrix_physical", lambda props: PhysicalBsdf(props))
    cells = sorted(p.parent.parent for p in args.run.glob("cells/*/truth_scene/scene.json"))
    if not cells:
        raise SystemExit(f"{args.run}: no cell has truth_scene/scene.json (set [outputs] truth_scene = true)")
    rows, failed = [], []
    for folder in (c / "truth_scene" for c in cells):
        record = json.loads((folder / "scene.json").read_text())
        if record["schema"] != 1:
            raise SystemExit(f"{folder}/scene.json: schema {record['schema']}, this script reads 1")
        FGD = FgdTable(read_exr(folder / record["fgd"]))
        cell = json.loads((folder.parent / "cell.json").read_text())
        truth = read_exr(folder / record["truth"])
        name = folder.parent.name
        try:
            scene = mi.load_dict(scene_dict(folder, record))
            check_uvs(scene, folder, record)
        except ValueError as e:
            rows.append(f"| {name} | left out: {e} |||||||")
            continue
        start = time.perf_counter()
        mean, se = render(scene, record["spp"], args.passes)
        seconds = time.perf_counter() - start
        r = compare(mean, se, truth)
        paths = record["width"] * record["height"] * record["spp"]
        truth_seconds = cell["truth"]["seconds"]
        native = native_paths_per_second(folder, record)
        subject = next(o for o in record["objects"] if o["subject"])
        ok = abs(r["z_mean"]) < 4.0 and r["z_rms"] < 1.3 and r["beyond_5"] < 0.005
        if not ok:
            failed.append(name)
        # Time to equal noise: time × variance per path, the truth's over Mitsuba's.
        speed = (truth_seconds * r["truth_relative_noise"] ** 2) / max(seconds * r["relative_noise"] ** 2, 1e-30)
        rows.append(
            f"| {name} | m {subject['metallic']:g} s {subject['smoothness']:g} | {r['ratio']:.5f} ± {r['ratio_se']:.5f} "
            f"| {r['z_mean']:+.2f} | {r['z_rms']:.3f} | {100 * r['beyond_5']:.2f} % "
            f"| {paths / truth_seconds / 1e6:.2f} / {paths / seconds / 1e6:.2f} / {native / 1e6:.2f} | {speed:.1f}× "
            f"| {'ok' if ok else 'FAIL'} |"
        )
    adapter = json.loads((args.run / "run.json").read_text()).get("adapter", {})
    text = "\n".join(
        [
            f"# Physical truth vs Mitsuba {mi.__version__} ({variant})",
            "",
            f"Run `{args.run}`; adapter {adapter.get('name', '?')}. Ratio: Mitsuba's mean luminance over the truth's, with its "
            "standard error; Z: the difference of the means in standard errors; z RMS: per pixel (1 when they agree "
            "within noise); M paths/s: the truth / Mitsuba with the same BSDF in Python (16 passes) / Mitsuba with its own compiled `principled` BSDF on the same scene (timed only); time to equal noise: how much longer the truth takes than Mitsuba to "
            "reach the same noise as Mitsuba with the same BSDF. Pass: |Z| < 4, z RMS < 1.3, under 0.5 % of pixels beyond 5σ.",
            "",
            "| cell | subject | ratio | Z | z RMS | beyond 5σ | M paths/s (truth / Mitsuba / native) | time to equal noise | |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
            *rows,
            "",
        ]
    )
    (args.run / "mitsuba_check.md").write_text(text)
    print(text)
    if failed:
        print(f"{len(failed)} case(s) disagree beyond noise: {', '.join(failed)}", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
