#!/usr/bin/env python3
"""Trims the project's shared cdd reference cones to the fields the contact tests read.

Usage: python3 testdata/contact/trim.py SOURCE_DIR   (the folder of the shared `cones/*.json`)
Writes testdata/contact/<case>.json next to this script. See README.md for the fields.
"""
import glob
import json
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
for path in sorted(glob.glob(os.path.join(sys.argv[1], "*.json"))):
    d = json.load(open(path))
    ref = d["reference_cdd_gmp_exact_input"]
    out = {
        "case": d["case"],
        "description": d["description"],
        "kind": d["kind"],
        "contacts": [{k: c[k] for k in ("name", "pos", "R", "half_size", "mu")} for c in d["meta"]["contacts"]],
        "generators": d["generators"]["float64"],
        "reference_facets": ref["facets_float64"],
        "reference_equations": ref["equations"],
        "reference_lineality_dim": ref["lineality_dim"],
        "cdd_float_time_ms": d["summary"]["time_ms"]["float"],
    }
    json.dump(out, open(os.path.join(here, os.path.basename(path)), "w"))
