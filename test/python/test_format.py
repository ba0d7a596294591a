"""Every C++ file of the package is formatted as .clang-format says (clang-format --dry-run finds nothing
to change): `clang-format -i <file>` before committing."""
import os
import subprocess

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def test_every_cpp_file_is_formatted():
    files = subprocess.run(["git", "ls-files", "*.cpp", "*.h"], capture_output=True, text=True, cwd=REPO,
                           check=True).stdout.split()
    assert len(files) > 100, files
    done = subprocess.run(["clang-format", "--dry-run", "--Werror"] + files, capture_output=True, text=True, cwd=REPO)
    unformatted = sorted({line.split(":")[0] for line in done.stderr.splitlines() if ": error:" in line})
    assert done.returncode == 0 and not unformatted, "not formatted (clang-format -i them): %s" % unformatted
