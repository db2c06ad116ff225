"""docs/firmware.md, "From an empty folder to your firmware, in both modes", done as a
user does it: a copy of examples/firmware built on its own with CMake (host library and,
with arm-none-eabi-gcc, the Cortex-M4 ELF), the page's two scenarios written as the page
gives them, and `packsim check` on both, which must print the page's PASS lines."""
from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SECTION = "## From an empty folder to your firmware, in both modes"


def _section() -> str:
    text = (REPO / "docs" / "firmware.md").read_text()
    start = text.index(SECTION)
    end = text.index("\n## ", start + len(SECTION))
    return text[start:end]


def _blocks(section: str, lang: str) -> list[str]:
    return re.findall(r"```" + lang + r"\n(.*?)```", section, re.S)


def _build(tmp_path: Path) -> Path:
    src = tmp_path / "mybms"
    shutil.copytree(REPO / "examples" / "firmware", src)
    cmake = shutil.which("cmake")
    if cmake is None:
        pytest.skip("cmake not installed")
    for cmd in ([cmake, "-S", str(src), "-B", str(src / "build"), f"-DPACKSIM_INCLUDE_DIR={REPO / 'bms'}",
                 "-DCMAKE_POLICY_VERSION_MINIMUM=3.5"],
                [cmake, "--build", str(src / "build")]):
        done = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True)
        assert done.returncode == 0, done.stdout + done.stderr
    return src / "build"


def test_the_pages_two_scenarios_pass_as_the_page_says(cli, tmp_path):
    section = _section()
    build = _build(tmp_path)
    assert (build / "libpacksim_example_bms.so").is_file()
    host, target = _blocks(section, "yaml")[:2]
    (tmp_path / "my_pack.yaml").write_text(host)
    (tmp_path / "my_pack_cm4.yaml").write_text(target)
    expected = [line for line in section.splitlines() if line.startswith("PASS")]
    assert len(expected) == 2, expected
    names = ["my_pack.yaml"]
    if shutil.which("arm-none-eabi-gcc"):
        # The ELF the page promises "when arm-none-eabi-gcc is installed".
        assert (build / "packsim_example_bms_cm4.elf").is_file(), sorted(p.name for p in build.iterdir())
        names.append("my_pack_cm4.yaml")
    done = subprocess.run([str(cli), "check", *names], cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    printed = [line for line in done.stdout.splitlines() if line.startswith("PASS")]
    assert printed == expected[:len(names)], done.stdout


def test_a_wrong_include_dir_is_a_configure_error_naming_the_folder(tmp_path):
    cmake = shutil.which("cmake")
    if cmake is None:
        pytest.skip("cmake not installed")
    src = tmp_path / "mybms"
    shutil.copytree(REPO / "examples" / "firmware", src)
    done = subprocess.run([cmake, "-S", str(src), "-B", str(src / "build"), f"-DPACKSIM_INCLUDE_DIR={REPO}",
                           "-DCMAKE_POLICY_VERSION_MINIMUM=3.5"], capture_output=True, text=True)
    assert done.returncode != 0
    assert "is not packsim's bms/ folder" in done.stderr and str(REPO) in done.stderr
