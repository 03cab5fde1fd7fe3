#!/usr/bin/env python3
"""How long `raytrace lsp` takes from a keystroke to its diagnostics.

Starts the server, opens a scene, then makes an edit that adds a mistake
and one that removes it, each as an editor sends it (didChange with the
whole text), and times didChange → publishDiagnostics. Prints the median
of several rounds.

  scripts/lsp_latency.py [--lines N] [--scene FILE] [--raytrace PATH] [--rounds K]

Without --scene, a generated scene of N lines (default 100000): constants,
materials, a function, and objects using them.
"""
import argparse, json, os, subprocess, sys, tempfile, time

def frame(msg):
    body = json.dumps(msg).encode()
    return b"Content-Length: %d\r\n\r\n" % len(body) + body

class Server:
    def __init__(self, exe):
        self.p = subprocess.Popen([exe, "lsp"], stdin=subprocess.PIPE, stdout=subprocess.PIPE)
        self.id = 0

    def send(self, msg):
        self.p.stdin.write(frame(msg))
        self.p.stdin.flush()

    def read(self):
        length = None
        while True:
            line = self.p.stdout.readline()
            if not line:
                raise SystemExit("the server closed its output")
            line = line.strip()
            if not line:
                break
            if line.lower().startswith(b"content-length:"):
                length = int(line.split(b":")[1])
        return json.loads(self.p.stdout.read(length))

    def request(self, method, params):
        self.id += 1
        self.send({"jsonrpc": "2.0", "id": self.id, "method": method, "params": params})
        while True:
            m = self.read()
            if m.get("id") == self.id:
                return m.get("result")

    def notify(self, method, params):
        self.send({"jsonrpc": "2.0", "method": method, "params": params})

    def diagnostics(self, uri, want):
        while True:
            m = self.read()
            if m.get("method") == "textDocument/publishDiagnostics" and m["params"]["uri"] == uri:
                d = m["params"]["diagnostics"]
                if want(d):
                    return d

def generate(lines):
    """A scene as a program writes one: a few constants, materials and a
    function, then one object per line using them."""
    out = ["camera { position <0, 20, 60>  look_at <0, 0, 0>  fov 50 }",
           "light { position <50, 80, 40> }",
           "fn post(h, r = 0.2) { cylinder { radius r  height h  translate <0, h / 2, 0> } }"]
    for k in range(20):
        out.append(f"let r{k} = 0.2 + {k} * 0.01")
    for k in range(50):
        out.append(f"material m{k} {{ colour rgb({k / 50:.2f}, 0.5, 0.5)  specular 0.3 }}")
    i = 0
    while len(out) < lines - 1:
        x, z = i % 300, i // 300
        kind = i % 4
        if kind == 0:
            out.append(f"sphere {{ centre <{x}, 0, {z}>  radius r{i % 20}  material m{i % 50} }}")
        elif kind == 1:
            out.append(f"box {{ min <{x}, -1, {z}>  max <{x + 0.5}, -0.5, {z + 0.5}>  material m{i % 50} }}")
        elif kind == 2:
            out.append(f"cylinder {{ centre <{x}, 1, {z}>  radius 0.1  height 2  rotate x {i % 90} }}")
        else:
            out.append(f"post({1 + i % 3}) {{ translate <{x}, 0, {z + 0.5}> }}")
        i += 1
    out.append("sphere { radius 1 }")
    return "\n".join(out[:lines]) + "\n"

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lines", type=int, default=100000)
    ap.add_argument("--scene")
    ap.add_argument("--raytrace", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "raytrace"))
    ap.add_argument("--rounds", type=int, default=5)
    a = ap.parse_args()
    if a.scene:
        path = os.path.abspath(a.scene)
        text = open(path).read()
    else:
        path = os.path.join(tempfile.mkdtemp(), "generated.rt")
        text = generate(a.lines)
        open(path, "w").write(text)
    uri = "file://" + path
    s = Server(a.raytrace)
    s.request("initialize", {"processId": None, "rootUri": None, "capabilities": {}})
    s.notify("initialized", {})
    t = time.perf_counter()
    s.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "rt", "version": 1, "text": text}})
    first = s.diagnostics(uri, lambda d: True)
    opened = time.perf_counter() - t
    print(f"{os.path.basename(path)}: {text.count(chr(10))} lines, {len(text)} bytes; "
          f"open → diagnostics {opened * 1000:.0f} ms ({len(first)} diagnostics)")
    # The mistake goes on the last line, after everything else is built.
    last = text.rstrip("\n").rfind("\n") + 1
    broken = text[:last] + "sphere { radus 1 }\n" + text[last:]
    broken_times, fixed_times = [], []
    version = 1
    for _ in range(a.rounds):
        version += 1
        t = time.perf_counter()
        s.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version}, "contentChanges": [{"text": broken}]})
        s.diagnostics(uri, lambda d: any("radus" in x["message"] for x in d))
        broken_times.append(time.perf_counter() - t)
        version += 1
        t = time.perf_counter()
        s.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version}, "contentChanges": [{"text": text}]})
        s.diagnostics(uri, lambda d: not any("radus" in x["message"] for x in d))
        fixed_times.append(time.perf_counter() - t)
    med = lambda v: sorted(v)[len(v) // 2] * 1000
    print(f"didChange → diagnostics, median of {a.rounds}: mistake shown {med(broken_times):.0f} ms, "
          f"mistake cleared {med(fixed_times):.0f} ms (includes the {25} ms debounce)")
    t = time.perf_counter()
    syms = s.request("textDocument/documentSymbol", {"textDocument": {"uri": uri}})
    print(f"documentSymbol: {len(syms or [])} symbols in {(time.perf_counter() - t) * 1000:.0f} ms")
    t = time.perf_counter()
    lines = text.count("\n")
    s.request("textDocument/hover", {"textDocument": {"uri": uri}, "position": {"line": lines - 2, "character": 2}})
    s.request("textDocument/completion", {"textDocument": {"uri": uri}, "position": {"line": lines - 2, "character": 9}})
    print(f"hover + completion at the end: {(time.perf_counter() - t) * 1000:.0f} ms")
    s.request("shutdown", None)
    s.notify("exit", None)
    s.p.wait(timeout=10)

if __name__ == "__main__":
    main()
