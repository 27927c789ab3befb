"""A minimal glTF 2.0 writer for tests: .gltf JSON with one base64 data-URI buffer.

Only what Facet's import tests need: float VEC3 attributes, u8/u16/u32 index accessors, nodes
with matrix or TRS, metallic-roughness materials. Written from the glTF 2.0 specification
(sections 3.6 buffers, 3.7 meshes, 3.5 nodes, 3.9 materials); no glTF library involved, so the
files test Facet's reader (tinygltf) against an independent writer.
"""
import base64
import json
import struct

FLOAT, U8, U16, U32 = 5126, 5121, 5123, 5125
TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN, LINES = 4, 5, 6, 1


class GltfWriter:
    def __init__(self):
        self.data = bytearray()
        self.doc = {"asset": {"version": "2.0", "generator": "facet gltf_writer.py"},
                    "buffers": [], "bufferViews": [], "accessors": [], "meshes": [],
                    "nodes": [], "scenes": [{"nodes": []}], "scene": 0, "materials": []}

    def _view(self, raw):
        while len(self.data) % 4:
            self.data.append(0)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.data),
                                        "byteLength": len(raw)})
        self.data += raw
        return len(self.doc["bufferViews"]) - 1

    def vec3(self, values):
        """A float VEC3 accessor of [(x, y, z), ...]; returns its index."""
        raw = b"".join(struct.pack("<3f", *v) for v in values)
        acc = {"bufferView": self._view(raw), "componentType": FLOAT, "count": len(values),
               "type": "VEC3"}
        import math
        if values and all(math.isfinite(c) for v in values for c in v):
            acc["min"] = [min(v[i] for v in values) for i in range(3)]
            acc["max"] = [max(v[i] for v in values) for i in range(3)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def indices(self, values, component=U16):
        fmt = {U8: "B", U16: "H", U32: "I"}[component]
        raw = struct.pack("<%d%s" % (len(values), fmt), *values)
        self.doc["accessors"].append({"bufferView": self._view(raw), "componentType": component,
                                      "count": len(values), "type": "SCALAR"})
        return len(self.doc["accessors"]) - 1

    def material(self, base=(1, 1, 1, 1), metallic=1.0, roughness=1.0, emissive=None,
                 strength=None, double_sided=False, **extra):
        m = {"pbrMetallicRoughness": {"baseColorFactor": list(base), "metallicFactor": metallic,
                                      "roughnessFactor": roughness},
             "doubleSided": double_sided}
        if emissive is not None:
            m["emissiveFactor"] = list(emissive)
        if strength is not None:
            m["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": strength}}
            self.use_extension("KHR_materials_emissive_strength")
        m.update(extra)
        self.doc["materials"].append(m)
        return len(self.doc["materials"]) - 1

    def use_extension(self, name, required=False):
        key = "extensionsRequired" if required else "extensionsUsed"
        for k in ("extensionsUsed", key):
            lst = self.doc.setdefault(k, [])
            if name not in lst:
                lst.append(name)

    def mesh(self, primitives):
        """primitives: dicts with positions, optional normals, indices (+ component), mode,
        material, extra attributes."""
        prims = []
        for p in primitives:
            attrs = {"POSITION": self.vec3(p["positions"])}
            if "normals" in p:
                attrs["NORMAL"] = self.vec3(p["normals"])
            attrs.update(p.get("attributes", {}))
            prim = {"attributes": attrs, "mode": p.get("mode", TRIANGLES)}
            if p.get("indices") is not None:
                prim["indices"] = self.indices(p["indices"], p.get("component", U16))
            if p.get("material") is not None:
                prim["material"] = p["material"]
            prims.append(prim)
        self.doc["meshes"].append({"primitives": prims})
        return len(self.doc["meshes"]) - 1

    def node(self, root=True, **fields):
        self.doc["nodes"].append(fields)
        i = len(self.doc["nodes"]) - 1
        if root:
            self.doc["scenes"][0]["nodes"].append(i)
        return i

    def write(self, path):
        """A .gltf with a base64 data-URI buffer, or (path ending .glb) a binary glTF: a
        12-byte header, a JSON chunk and a BIN chunk, each padded to 4 bytes (spec 4.4)."""
        glb = path.endswith(".glb")
        if glb:
            self.doc["buffers"] = [{"byteLength": len(self.data)}]
        else:
            uri = ("data:application/octet-stream;base64," +
                   base64.b64encode(bytes(self.data)).decode())
            self.doc["buffers"] = [{"byteLength": len(self.data), "uri": uri}]
        doc = {k: v for k, v in self.doc.items() if v != []}
        if not glb:
            with open(path, "w") as f:
                json.dump(doc, f, indent=1)
                f.write("\n")
            return
        text = json.dumps(doc).encode()
        text += b" " * (-len(text) % 4)
        binary = bytes(self.data) + b"\0" * (-len(self.data) % 4)
        chunks = (struct.pack("<I4s", len(text), b"JSON") + text +
                  struct.pack("<I4s", len(binary), b"BIN\0") + binary)
        with open(path, "wb") as f:
            f.write(struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks)
