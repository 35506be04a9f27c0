"""Hard inputs are treated the same way by every command: a directory or a missing file
is an I/O error (exit 2, saying which), binary or non-UTF-8 text is I001 and an empty
file I002 (located, exit 1), and raw bytes never reach the terminal."""

from __future__ import annotations

import json

import pytest

import stampc
from stampc.cli import main
from stampc.diagnostics import StampcError
from stampc.inputs import read_input_text

from .paths import EXAMPLES

FILE_COMMANDS = ["check", "fmt", "compile", "solve", "refine"]
BINARY = b"domain x\n\x00\x00\x01\x1b[2J\xff\xfe binary\n"


@pytest.fixture()
def files(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "folder.stamp").mkdir()
    (tmp_path / "binary.stamp").write_bytes(BINARY)
    (tmp_path / "latin1.stamp").write_bytes("domain caf\xe9\n".encode("latin-1"))
    (tmp_path / "empty.stamp").write_bytes(b"")
    (tmp_path / "blank.stamp").write_bytes(b"  \n\t\n")
    return tmp_path


@pytest.mark.parametrize("command", FILE_COMMANDS)
def test_a_directory_is_reported_as_a_directory(command, files, capsys):
    assert main([command, "folder.stamp"]) == 2
    err = capsys.readouterr().err
    assert "folder.stamp: it is a directory, not a file" in err
    assert "no such file" not in err and "Traceback" not in err


@pytest.mark.parametrize("command", FILE_COMMANDS)
def test_a_missing_file_is_an_io_error(command, files, capsys):
    assert main([command, "nope.stamp"]) == 2
    assert "cannot read nope.stamp: no such file" in capsys.readouterr().err


@pytest.mark.parametrize("command", FILE_COMMANDS)
def test_binary_input_is_a_located_diagnostic_without_raw_bytes(command, files, capsys):
    assert main([command, "binary.stamp"]) == 1
    captured = capsys.readouterr()
    text = captured.out + captured.err
    assert "binary.stamp:2:1: I001 error: not UTF-8 text: NUL byte at byte offset 9" in text
    assert not any(c in text for c in "\x00\x01\x1b")


@pytest.mark.parametrize("command", FILE_COMMANDS)
def test_non_utf8_input_names_the_byte(command, files, capsys):
    assert main([command, "latin1.stamp"]) == 1
    captured = capsys.readouterr()
    assert "latin1.stamp:1:11: I001 error: not UTF-8 text: byte 0xe9 at byte offset 10" in \
        captured.out + captured.err


@pytest.mark.parametrize("command", FILE_COMMANDS)
@pytest.mark.parametrize("name", ["empty.stamp", "blank.stamp"])
def test_an_empty_file_is_the_same_error_everywhere(command, name, files, capsys):
    assert main([command, name]) == 1
    captured = capsys.readouterr()
    assert f"{name}:1:1: I002 error: empty file" in captured.out + captured.err


def test_check_reports_unreadable_files_beside_the_others_in_json(files, capsys):
    good = str(EXAMPLES / "shelf2d" / "domain.stamp")
    assert main(["check", "--format", "json", "binary.stamp", good]) == 1
    diags = json.loads(capsys.readouterr().out)
    assert [d["code"] for d in diags] == ["I001"]
    assert diags[0]["span"]["file"] == "binary.stamp" and diags[0]["span"]["line"] == 2


def test_the_api_raises_the_same_diagnostics(files):
    with pytest.raises(StampcError) as info:
        stampc.compile(files / "empty.stamp")
    assert [d.code for d in info.value.diagnostics] == ["I002"]
    with pytest.raises(IsADirectoryError):
        stampc.compile(files / "folder.stamp")


def test_execute_treats_its_policy_file_the_same_way(files, capsys):
    assert main(["execute", "binary.stamp"]) == 1
    assert "I001" in capsys.readouterr().err
    assert main(["execute", "folder.stamp"]) == 2
    (files / "policy.json").write_text('{"format": "stampc-policy",\n "files": [}',
                                       encoding="utf-8")
    assert main(["execute", "policy.json"]) == 1
    assert "policy.json:2:12: I003 error: not valid JSON" in capsys.readouterr().err
    (files / "other.json").write_text('{"format": "something else"}', encoding="utf-8")
    assert main(["execute", "other.json"]) == 1
    assert "I003 error: not a stampc policy file" in capsys.readouterr().err


def test_a_byte_order_mark_is_dropped(tmp_path):
    path = tmp_path / "bom.stamp"
    path.write_bytes(b"\xef\xbb\xbfdomain d\n")
    assert read_input_text(path) == "domain d\n"


def test_check_accepts_a_byte_order_mark(tmp_path, capsys):
    path = tmp_path / "bom.stamp"
    path.write_bytes(b"\xef\xbb\xbf" + (EXAMPLES / "shelf2d" / "domain.stamp").read_bytes())
    assert main(["check", str(path)]) == 0
    assert "0 errors" in capsys.readouterr().out
