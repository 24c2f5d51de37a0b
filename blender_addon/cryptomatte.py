"""Cryptomatte and index passes, as Cycles writes them: CryptoObject00,
CryptoMaterial00, CryptoAsset00, ... (the view layer's Cryptomatte Object /
Material / Asset and its Levels), each pass two ranks of (id, coverage), and
the render's metadata (name, hash, conversion, manifest per layer) that
compositors read names from.

The core reports, per pixel and per layer of matte keys (objects, materials,
assets: Export.kwargs(mattes=...)), the keys of most coverage, most first
(RenderSettings.matte_ranks). Here each key becomes its name's id: the
Cryptomatte specification's MurmurHash3 (x86, 32 bits, seed 0) of the name's
UTF-8 bytes, its bits read as a float32 whose exponent is kept off 0 and 255.

The Object Index and Material Index passes (IndexOB, IndexMA) come from the
same ranks: the Pass Index of the object and material covering most of the
pixel (Cycles takes its first sample's, so edge pixels may differ).
"""
from __future__ import annotations

import json
import struct

import numpy as np

# (view layer flag, pass name prefix, the layer of keys it reads)
LAYERS = (("use_pass_cryptomatte_object", "CryptoObject", "object"),
          ("use_pass_cryptomatte_material", "CryptoMaterial", "material"),
          ("use_pass_cryptomatte_asset", "CryptoAsset", "asset"))
# (view layer flag, the pass's source in the result writer's arrays, the layer whose pass index it shows)
INDEX_PASSES = (("use_pass_object_index", "IndexOB", "object"),
                ("use_pass_material_index", "IndexMA", "material"))
MAX_RANKS = 16      # RenderSettings.matte_ranks' maximum


def murmur3_32(data: bytes, seed: int = 0) -> int:
    """MurmurHash3's 32-bit x86 hash of `data`."""
    c1, c2, mask = 0xCC9E2D51, 0x1B873593, 0xFFFFFFFF
    h = seed & mask
    rotl = lambda x, r: ((x << r) | (x >> (32 - r))) & mask
    full = len(data) // 4 * 4
    for (k,) in struct.iter_unpack("<I", data[:full]):
        k = rotl((k * c1) & mask, 15) * c2 & mask
        h = (rotl(h ^ k, 13) * 5 + 0xE6546B64) & mask
    tail = data[full:]
    if tail:
        k = int.from_bytes(tail, "little")
        h ^= rotl((k * c1) & mask, 15) * c2 & mask
    h ^= len(data)
    h ^= h >> 16
    h = (h * 0x85EBCA6B) & mask
    h ^= h >> 13
    h = (h * 0xC2B2AE35) & mask
    return h ^ (h >> 16)


def id_float(name: str) -> float:
    """The float32 id Cryptomatte gives `name` (its hash's exponent kept within 1..254)."""
    h = murmur3_32(name.encode("utf-8"))
    exponent = min(max((h >> 23) & 0xFF, 1), 254)
    bits = (h & 0x807FFFFF) | (exponent << 23)
    return float(np.array(bits, np.uint32).view(np.float32))


def _on(view_layer, flag) -> bool:
    return getattr(view_layer, flag, False) is True


def levels(view_layer) -> int:
    """Ranks per pixel the view layer asks for (Cryptomatte > Levels), 0 with no layer enabled."""
    if not any(_on(view_layer, flag) for flag, _, _ in LAYERS):
        return 0
    return max(2, min(MAX_RANKS, int(getattr(view_layer, "pass_cryptomatte_depth", 6))))


def ranks(view_layer) -> int:
    """RenderSettings.matte_ranks for the view layer's passes (0: none asks for mattes)."""
    return levels(view_layer) or (1 if any(_on(view_layer, flag) for flag, _, _ in INDEX_PASSES) else 0)


def key_layers(view_layer) -> tuple[str, ...]:
    """The layers of matte keys the view layer's passes read, in the core's order."""
    wanted = {layer for flag, _, layer in LAYERS + INDEX_PASSES if _on(view_layer, flag)}
    return tuple(layer for layer in ("object", "material", "asset") if layer in wanted)


def pass_names(view_layer) -> list[str]:
    """The Cryptomatte passes to register: per enabled layer, one of 4 channels per two ranks."""
    count = (levels(view_layer) + 1) // 2
    return [f"{prefix}{i:02d}" for flag, prefix, _ in LAYERS if _on(view_layer, flag) for i in range(count)]


class Mattes:
    """Turns the core's per-pixel (key, coverage) ranks into the view layer's passes.

    tables: per layer of keys (key_layers()), each key's (name, pass index)."""

    def __init__(self, view_layer, tables: dict):
        self.layer_name = view_layer.name
        self.levels = levels(view_layer)
        self.order = key_layers(view_layer)
        self.tables = tables
        self.layers = [(prefix, layer) for flag, prefix, layer in LAYERS if _on(view_layer, flag)]
        self.indices = [(source, layer) for flag, source, layer in INDEX_PASSES if _on(view_layer, flag)]
        # per layer: each key's id and pass index, then the key -1's (0, 0) at the end
        self.ids = {layer: np.array([id_float(name) for name, _ in table] + [0.0], np.float32)
                    for layer, table in tables.items()}
        self.pass_index = {layer: np.array([index for _, index in table] + [0], np.float32)
                           for layer, table in tables.items()}

    def passes(self, keys: np.ndarray, coverage: np.ndarray) -> dict:
        """Pass name (or index source) -> (h, w, 4) (Cryptomatte) or (h, w, 1) (index) float32,
        from (h, w, layers, R) keys and coverage."""
        out = {}
        for source, layer in self.indices:
            out[source] = self.pass_index[layer][keys[:, :, self.order.index(layer), :1]]
        count = (self.levels + 1) // 2
        for prefix, layer in self.layers:
            li = self.order.index(layer)
            kept = min(keys.shape[-1], 2 * count)
            pairs = np.zeros(keys.shape[:2] + (2 * count, 2), np.float32)
            pairs[..., :kept, 0] = self.ids[layer][keys[:, :, li, :kept]]
            pairs[..., :kept, 1] = coverage[:, :, li, :kept]
            pairs = pairs.reshape(keys.shape[:2] + (count, 4))
            for i in range(count):
                out[f"{prefix}{i:02d}"] = pairs[..., i, :]
        return out

    def metadata(self) -> dict[str, str]:
        """The render's Cryptomatte metadata: per layer its name, hash, conversion and manifest."""
        out = {}
        for prefix, layer in self.layers:
            name = f"{self.layer_name}.{prefix}"
            key = f"cryptomatte/{murmur3_32(name.encode('utf-8')):08x}"[:19]
            manifest = {n: f"{murmur3_32(n.encode('utf-8')):08x}" for n, _ in sorted(set(self.tables[layer]))}
            out.update({f"{key}/name": name, f"{key}/hash": "MurmurHash3_32",
                        f"{key}/conversion": "uint32_to_float32",
                        f"{key}/manifest": json.dumps(manifest, separators=(",", ":"))})
        return out
