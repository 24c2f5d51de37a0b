"""Cryptomatte and index passes, as Cycles writes them: CryptoObject00, CryptoMaterial00,
CryptoAsset00, ... (the view layer's Cryptomatte Object / Material / Asset and
its Levels), each pass two ranks of (id, coverage), and the render's metadata
(name, hash, conversion, manifest per layer) that compositors read names from.

The core reports, per pixel, the matte keys of most coverage (RenderSettings.
matte_ranks; a key per distinct object and material pair, Export.matte_table).
Here each layer's ids are merged by name (an object of two materials is one
object), sorted by coverage and encoded. An id is the Cryptomatte
specification's: MurmurHash3 (x86, 32 bits, seed 0) of the name's UTF-8
bytes, its bits read as a float32 whose exponent is kept off 0 and 255.

The Object Index and Material Index passes (IndexOB, IndexMA) come from the
same ranks: the Pass Index of the object and material covering most of the
pixel (Cycles takes its first sample's, so edge pixels may differ).
"""
from __future__ import annotations

import json
import struct

import numpy as np

# What a matte key's entry (Export.matte_names) holds, by position.
OBJECT, ASSET, OBJECT_INDEX, MATERIAL, MATERIAL_INDEX = range(5)
# (view layer flag, pass name prefix, the entry's name the layer's ids hash)
LAYERS = (("use_pass_cryptomatte_object", "CryptoObject", OBJECT),
          ("use_pass_cryptomatte_material", "CryptoMaterial", MATERIAL),
          ("use_pass_cryptomatte_asset", "CryptoAsset", ASSET))
# (view layer flag, pass name, the entry's pass index it shows)
INDEX_PASSES = (("use_pass_object_index", "IndexOB", OBJECT_INDEX),
                ("use_pass_material_index", "IndexMA", MATERIAL_INDEX))
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


def levels(view_layer) -> int:
    """Ranks per pixel the view layer asks for (Cryptomatte > Levels), 0 with no layer enabled."""
    if not any(getattr(view_layer, flag, False) is True for flag, _, _ in LAYERS):
        return 0
    return max(2, min(MAX_RANKS, int(getattr(view_layer, "pass_cryptomatte_depth", 6))))


def index_passes(view_layer) -> list[tuple[str, int]]:
    """(pass name, entry position) of the index passes the view layer enables."""
    return [(name, which) for flag, name, which in INDEX_PASSES if getattr(view_layer, flag, False) is True]


def ranks(view_layer) -> int:
    """RenderSettings.matte_ranks for the view layer's passes (0: none asks for mattes)."""
    wanted = levels(view_layer)
    if wanted:   # (a few more keys than ranks: an object's materials are merged into one id)
        return min(MAX_RANKS, wanted + 2)
    return 1 if index_passes(view_layer) else 0


def enabled(view_layer) -> list[tuple[str, int]]:
    """(pass name prefix, names index) of the layers the view layer enables."""
    return [(prefix, which) for flag, prefix, which in LAYERS if getattr(view_layer, flag, False) is True]


def pass_names(view_layer) -> list[str]:
    """The passes to register: per enabled layer, one of 4 channels per two ranks."""
    count = (levels(view_layer) + 1) // 2
    return [f"{prefix}{i:02d}" for prefix, _ in enabled(view_layer) for i in range(count)]


class Mattes:
    """Turns the core's per-pixel (key, coverage) ranks into the view layer's Cryptomatte passes.

    names: per matte key, (object, asset, material) names (material None: none)."""

    def __init__(self, view_layer, names: list[tuple]):
        self.layer_name = view_layer.name
        self.levels = levels(view_layer)
        self.layers = enabled(view_layer)
        self.names = names
        self.indices = index_passes(view_layer)
        # per index pass: each key's pass index, and the key -1's (0) at the end
        self.index_values = {name: np.array([n[which] for n in names] + [0], np.float32)
                             for name, which in self.indices}
        # per layer: each key's id (0 where it has no name), and the key -1's at the end
        self.ids = {}
        for prefix, which in self.layers:
            ids = [id_float(n[which]) if n[which] is not None else 0.0 for n in names]
            self.ids[prefix] = np.array(ids + [0.0], np.float32)

    def passes(self, keys: np.ndarray, coverage: np.ndarray) -> dict:
        """Pass name -> (h, w, 4) (Cryptomatte) or (h, w, 1) (index) float32 from (h, w, R)
        keys and coverage."""
        out = {name: self.index_values[name][keys[..., :1]] for name, _ in self.indices}
        for prefix, _ in self.layers:
            ids = self.ids[prefix][keys]             # (key -1 reads the last entry: 0)
            cov = np.where(ids != 0, coverage, 0.0).astype(np.float32)
            ranks = keys.shape[-1]
            for i in range(1, ranks):                # one entry per id: later equal ids added to the first
                for j in range(i):
                    same = (ids[..., j] == ids[..., i]) & (cov[..., i] > 0)
                    cov[..., j] += np.where(same, cov[..., i], 0.0)
                    cov[..., i] = np.where(same, 0.0, cov[..., i])
            order = np.argsort(-cov, axis=-1, kind="stable")
            cov = np.take_along_axis(cov, order, -1)
            ids = np.where(cov > 0, np.take_along_axis(ids, order, -1), 0.0)
            count = (self.levels + 1) // 2
            pairs = np.zeros(keys.shape[:2] + (2 * count, 2), np.float32)
            kept = min(ranks, 2 * count)
            pairs[..., :kept, 0] = ids[..., :kept]
            pairs[..., :kept, 1] = cov[..., :kept]
            pairs = pairs.reshape(keys.shape[:2] + (count, 4))
            for i in range(count):
                out[f"{prefix}{i:02d}"] = pairs[..., i, :]
        return out

    def metadata(self) -> dict[str, str]:
        """The render's Cryptomatte metadata: per layer its name, hash, conversion and manifest."""
        out = {}
        for prefix, which in self.layers:
            layer = f"{self.layer_name}.{prefix}"
            key = f"cryptomatte/{murmur3_32(layer.encode('utf-8')):08x}"[:19]
            names = sorted({n[which] for n in self.names if n[which] is not None})
            manifest = {name: f"{murmur3_32(name.encode('utf-8')):08x}" for name in names}
            out.update({f"{key}/name": layer, f"{key}/hash": "MurmurHash3_32",
                        f"{key}/conversion": "uint32_to_float32",
                        f"{key}/manifest": json.dumps(manifest, separators=(",", ":"))})
        return out
