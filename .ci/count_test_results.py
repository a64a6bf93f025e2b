#!/usr/bin/python3
"""Counts test cases in catkin's JUnit XML results (catkin_test_results counts gtest suites twice).

Prints one line per failed case and returns (passed, failed, skipped). A test program that did not
finish (killed, crashed, hung past its limit) leaves no result of its own: `--unfinished N` counts N
such programs as failures, so they cannot pass unnoticed."""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path


def count(results_dir):
    passed = failed = skipped = 0
    files = sorted(Path(results_dir).rglob("*.xml"))
    for path in files:
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError as error:
            print(f"unreadable result file {path}: {error}")
            failed += 1
            continue
        for case in root.iter("testcase"):
            name = f"{case.get('classname')}.{case.get('name')}"
            if case.find("failure") is not None or case.find("error") is not None:
                print(f"FAILED: {name} ({path.name})")
                failed += 1
            elif case.find("skipped") is not None or case.get("status") == "notrun":
                skipped += 1
            else:
                passed += 1
    return len(files), passed, failed, skipped


if __name__ == "__main__":
    unfinished = 0
    if len(sys.argv) == 4 and sys.argv[2] == "--unfinished":
        unfinished = int(sys.argv[3])
    n_files, passed, failed, skipped = count(sys.argv[1])
    if unfinished:
        print(f"FAILED: {unfinished} test program(s) did not finish (see build/run_tests.log)")
        failed += unfinished
    print(f"{n_files} result files")
    print(f"{passed} passed, {failed} failed, {skipped} skipped")
    sys.exit(1 if failed or passed == 0 else 0)
