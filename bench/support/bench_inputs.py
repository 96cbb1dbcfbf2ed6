"""What the bench's plot and table scripts share: reading their inputs, so that a missing or
malformed file ends with one line naming it (exit 1) instead of a traceback.

A script imports it with
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
    from bench_inputs import load_json, read_csv, read_bytes, require_dir, require_module
It uses the standard library only, so that it loads under any python3 and can say what is missing.
"""
import csv
import importlib
import json
import os
import sys


def _fail(path, why):
    sys.exit(f"{os.path.basename(sys.argv[0])}: {path}: {why}")


def require_module(name, package):
    """The imported module, or exit 1 with one line naming the Debian package: the scripts run
    with /usr/bin/python3, whose matplotlib and numpy come from Debian; another python3 on PATH
    (pyenv, a venv) may have neither."""
    try:
        return importlib.import_module(name)
    except ImportError:
        sys.exit(f"{os.path.basename(sys.argv[0])}: needs the Python module {name.split('.')[0]}, which "
                 f"{sys.executable} does not have: run the script with /usr/bin/python3 "
                 f"(Debian package {package})")


def read_bytes(path):
    """The file's bytes."""
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as e:
        _fail(path, e.strerror or str(e))


def load_json(path):
    """The parsed JSON file."""
    try:
        return json.loads(read_bytes(path))
    except ValueError as e:  # json.JSONDecodeError and UnicodeDecodeError
        _fail(path, f"not JSON ({e})")


def read_csv(path, columns):
    """The CSV file's rows as dicts; every name in columns must be in its header."""
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            missing = [c for c in columns if c not in (reader.fieldnames or [])]
            if missing:
                _fail(path, f"no column {', '.join(missing)} (not the CSV this script reads?)")
            return list(reader)
    except OSError as e:
        _fail(path, e.strerror or str(e))


def require_dir(path):
    """Ends the script unless path is an existing folder (the plots are written there)."""
    if not os.path.isdir(path):
        _fail(path, "no such folder")
