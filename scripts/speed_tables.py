"""The README's Speed tables from one set of benchmark outputs (issue 23).

  .venv/bin/python scripts/speed_tables.py docs/speed_<date>.json

The JSON holds what scripts/speed.sh collects: "native" (`cargo bench
--bench inbetween`), "wasm" (`node tests/web/bench_page.mjs`), "ort" (`node
tests/web/bench_ort_page.mjs`) and "profile" (`cargo run --release --example
profile_models`). Prints two Markdown tables: the in-betweening per length
(native and wasm, the default pipeline and the generator pipeline, beside
thesis Table 5.3), and per bundled model tract natively, tract in wasm and
onnxruntime-web (and tract with the worker's relaxed-SIMD build where the
bench ran it, with the matrix kernel chosen and with tract's own), with what
tract's own profile in wasm puts first.
"""
import json
import sys

TABLE_5_3 = {512: 59, 1024: 101, 2048: 188, 4096: 329}  # Titan Xp, full-width model (ms)


def fmt(v, nd=1):
    return "-" if v is None else f"{v:.{nd}f}"


def inbetween(d):
    nat = {r["frames"]: r for r in d["native"]["rows"]}
    web = {r["frames"]: r for r in d["wasm"]["rows"]}
    sizes = sorted(web)
    rows = []

    def row(label, f, bold=False):
        cells = [f(n) for n in sizes]
        if bold:
            label, cells = f"**{label}**", [f"**{c}**" for c in cells]
        rows.append(f"| {label} | " + " | ".join(cells) + " |")

    row("native: the default for whole-pose keys (residual network)", lambda n: fmt(nat.get(n, {}).get("residual_ms")))
    row("native: generator pipeline, total (generator, RC-FK, path, post with foot locking)",
        lambda n: fmt(nat.get(n, {}).get("total_ms")))
    row("native: SLERP+LERP", lambda n: fmt(nat.get(n, {}).get("slerp_lerp_ms"), 2))
    row("wasm: residual network alone", lambda n: fmt(web[n].get("residual_network_ms"), 0))
    row("wasm total: the default for whole-pose keys (`total_ms`)", lambda n: fmt(web[n]["total_ms"], 0), bold=True)
    row("wasm: its first call at that length (`first_call_ms`)", lambda n: fmt(web[n]["first_call_ms"], 0))
    if any("simd128_total_ms" in web[n] for n in sizes):
        row("wasm: the default with the plain SIMD build (`simd128_total_ms`; `wasm`: "
            f"{web[sizes[0]].get('wasm', '-')} above)", lambda n: fmt(web[n].get("simd128_total_ms"), 0))
        row("wasm: first read of the default result's BVH text (`bvh_ms`)", lambda n: fmt(web[n].get("bvh_ms"), 0))
    g = lambda n, k: web[n]["generator_pipeline"][k]  # noqa: E731
    row("wasm: generator pipeline, generator", lambda n: fmt(g(n, "generator_ms"), 0))
    row("wasm: generator pipeline, path predictor", lambda n: fmt(g(n, "path_ms"), 0))
    row("wasm: generator pipeline, total", lambda n: fmt(g(n, "total_ms"), 0))
    row("wasm: SLERP+LERP with BVH and FK", lambda n: fmt(web[n]["slerp_lerp_ms_with_bvh_and_fk"], 0))
    row("thesis Table 5.3 (Titan Xp GPU, full-width model)", lambda n: str(TABLE_5_3.get(n, "-")))
    head = "| frames | " + " | ".join(str(n) for n in sizes) + " |\n|---|" + "---|" * len(sizes)
    return head + "\n" + "\n".join(rows)


def models(d):
    native = {r["model"]: r for r in d["profile"]["rows"]}
    relaxed = any(r.get("tract_relaxed_ms") is not None for r in d["ort"]["rows"])
    # since session 27: the relaxed build again with tract's own 8x8 matrix kernel
    tk = any(r.get("tract_relaxed_tract_kernel_ms") is not None for r in d["ort"]["rows"])
    out = ["| model (inputs) | tract, native | tract, wasm | onnxruntime-web | tract / ORT (wasm) "
           + ("| tract, wasm relaxed SIMD (the worker's build) | its / ORT " if relaxed else "")
           + ("| the same with tract's 8x8 kernel " if tk else "")
           + ("| tract's first operator (matrix kernel) in the worker's build, its own profile "
              if any(r.get("tract_profile_build") == "relaxed-simd" for r in d["ort"]["rows"])
              else "| tract's first operator in wasm (its own profile) ")
           + "| that operator's share of tract's time / ORT's whole run |",
           "|---|---|---|---|---|---|---|" + ("---|---|" if relaxed else "") + ("---|" if tk else "")]
    for r in d["ort"]["rows"]:
        n = native.get(r["model"], {})
        top = (r.get("tract_profile_wasm") or [None])[0]
        # since session 28 products are counted per matrix kernel, named
        first = (f"{top['op']}" + (f" on `{top['kernel']}`" if top.get("kernel") else "")
                 + f" {top['share'] * 100:.0f}%") if top else "-"
        # the operator's time as its share of tract's measured run in the
        # build profiled (profiled runs build fresh state and read a coarse
        # clock, so their absolute times run high; the shares hold)
        run = r.get("tract_relaxed_ms") if r.get("tract_profile_build") == "relaxed-simd" else r["tract_ms"]
        alone = f"{top['share'] * run / r['onnxruntime_web_ms']:.2f}" if top and run and r["onnxruntime_web_ms"] else "-"
        rel = (f"{fmt(r.get('tract_relaxed_ms'))} | {fmt(r.get('ratio_relaxed'), 2)} | " if relaxed else "")
        rel += f"{fmt(r.get('tract_relaxed_tract_kernel_ms'))} | " if tk else ""
        out.append(f"| {r['model']} | {fmt(n.get('best_profiled_run_ms'))} | {fmt(r['tract_ms'])} | "
                   f"{fmt(r['onnxruntime_web_ms'])} | {r['ratio']:.2f} | {rel}{first} | {alone} |")
    return "\n".join(out)


def main():
    d = json.load(open(sys.argv[1]))
    print(f"Measured {d.get('date', '?')}, {d.get('machine', '')} (ms).\n")
    print(inbetween(d))
    print()
    print(models(d))


if __name__ == "__main__":
    main()
