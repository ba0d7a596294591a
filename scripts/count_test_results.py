#!/usr/bin/env python3
"""Counts test cases in the JUnit XML files that gtest and rostest wrote; prints failures and a closing
line `N passed, N failed`. Exit status 1 when anything failed or no test ran."""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

root = Path(sys.argv[1] if len(sys.argv) > 1 else "build/test_results")
passed, failed, skipped = 0, [], []
for path in sorted(root.rglob("*.xml")):
    try:
        tree = ET.parse(path)
    except ET.ParseError as e:
        failed.append(f"{path.name}: unreadable result file ({e})")
        continue
    for case in tree.iter("testcase"):
        name = f"{case.get('classname', '')}.{case.get('name', '')}"
        if case.find("failure") is not None or case.find("error") is not None:
            node = case.find("failure") if case.find("failure") is not None else case.find("error")
            failed.append(f"{name}: {(node.get('message') or node.text or '').strip()[:300]}")
        elif case.find("skipped") is not None or case.get("status") == "notrun":
            node = case.find("skipped")
            why = (node.get("message") or "").strip().splitlines()[-1:] if node is not None else []
            skipped.append(f"{name}: {why[0] if why else 'not run'}")
        else:
            passed += 1
for f in failed:
    print(f"FAILED {f}")
for s in skipped:
    print(f"SKIPPED {s}")
print(f"{passed} passed, {len(failed)} failed")
sys.exit(1 if failed or passed == 0 else 0)
