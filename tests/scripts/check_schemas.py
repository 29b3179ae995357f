#!/usr/bin/python3
"""Checks result files against their JSON Schemas (docs/schemas/, python3-jsonschema).

Usage: check_schemas.py SCHEMA FILE [SCHEMA FILE ...]
SCHEMA is a schema's name: measurements, metrics, claims or recommendation. Prints one line per
file; exits 1 at the first file that does not conform, naming where and why.
"""
import json
import os
import sys

import jsonschema

SCHEMAS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs", "schemas")


def validators():
    schemas = {}
    for name in sorted(os.listdir(SCHEMAS)):
        with open(os.path.join(SCHEMAS, name)) as f:
            schema = json.load(f)
        jsonschema.Draft202012Validator.check_schema(schema)
        schemas[schema["$id"]] = schema
    # the schemas refer to each other by their $id (metrics.json is a row of measurements.json)
    return {key.split(".")[0]: jsonschema.Draft202012Validator(
        schema, resolver=jsonschema.RefResolver(key, schema, store=schemas)) for key, schema in schemas.items()}


def main(args):
    if len(args) < 2 or len(args) % 2:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    checks = validators()
    for name, path in zip(args[::2], args[1::2]):
        with open(path) as f:
            data = json.load(f)
        error = jsonschema.exceptions.best_match(checks[name].iter_errors(data))
        if error:
            print("FAIL: %s is not %s.schema.json: at /%s: %s" % (
                path, name, "/".join(str(p) for p in error.absolute_path), error.message[:200]))
            return 1
        print("ok: %s conforms to docs/schemas/%s.schema.json" % (path, name))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
