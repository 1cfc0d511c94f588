import math
from symkin.model.catalogue import data

def fixed_repeated(n):
    d = data("fourbar_appendix"); d["fixed"] = ["A", "D"] * (n // 2); return d

def big_link(n):
    d = data("fourbar_appendix")
    for k in range(n):
        d["nodes"][f"N{k}"] = [5 + math.cos(k), 5 + math.sin(k) + k * 1e-3]
    d["links"]["body"] = ["C"] + [f"N{k}" for k in range(n)]
    return d

def all_fixed(n):
    nodes = {f"N{k}": [float(k), float(k % 7)] for k in range(n)}
    links = {f"L{k}": [f"N{k}", f"N{k+1}"] for k in range(n - 1)}
    return {"name": "all fixed", "dim": 2, "fixed": list(nodes), "nodes": nodes, "links": links}

def chain(n, key):
    nodes = {f"N{k}": [float(k), 0.5 * (k % 2)] for k in range(n + 1)}
    links = {f"L{k}": [f"N{k}", f"N{k+1}"] for k in range(n)}
    d = {"name": "chain", "dim": 2, "fixed": ["N0"], "nodes": nodes, "links": links}
    d[key] = [{"rotation": f"L{k}"} for k in range(n)]
    return d

def inputs(n): return chain(n, "inputs")
def outputs(n): return chain(n, "outputs")

def identical_sliders(n):
    d = data("slider_crank"); d["sliders"] = d["sliders"] * n; return d

CASES = {"fixed_repeated": fixed_repeated, "big_link": big_link, "all_fixed": all_fixed,
         "inputs": inputs, "outputs": outputs, "identical_sliders": identical_sliders}

def dup_inputs(n):
    d = data("fourbar_appendix"); d["inputs"] = [{"rotation": "crank"}] * n; return d

def dup_outputs(n):
    d = data("fourbar_appendix"); d["outputs"] = [{"rotation": "rocker"}] * n; return d

def many_velocity_outputs(n):
    d = chain(n, "outputs"); d["outputs"] = [{"velocity": f"N{k+1}"} for k in range(n)]; return d

CASES.update(dup_inputs=dup_inputs, dup_outputs=dup_outputs, many_velocity_outputs=many_velocity_outputs)
