#!/usr/bin/env python3
"""Fails, naming them, if any test of the build directory argv[1] has no ctest TIMEOUT (every test has
one so that a hang fails by name: CMakeLists.txt SPINMOTOR_TEST_TIMEOUT, tests/CMakeLists.txt)."""
import json
import subprocess
import sys

ctest, build = sys.argv[1], sys.argv[2]
listing = json.loads(subprocess.run([ctest, "--show-only=json-v1", "--test-dir", build], check=True,
                                    capture_output=True, text=True).stdout)
tests = listing["tests"]
missing = [t["name"] for t in tests
           if not any(p["name"] == "TIMEOUT" and p["value"] > 0 for p in t.get("properties", []))]
for name in missing:
    print(f"no TIMEOUT: {name}")
print(f"check_timeouts: {len(tests) - len(missing)} of {len(tests)} tests have a TIMEOUT")
sys.exit(1 if missing else 0)
