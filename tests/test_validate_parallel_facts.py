"""validate/facts.py: what workers read of a file for the checks across files, learnt by the
run's process (kept in a temporary file of its own, one number a file in memory) and handed
out once; anything not learnt is read where it is asked for, so a check finds the same either way."""

from __future__ import annotations

import multiprocessing
from pathlib import Path

import pytest

from pdsgen.validate import facts

READS: list[str] = []


@facts.fact("pdsgen-test")
def _size(path: Path) -> int:
    READS.append(path.name)
    return path.stat().st_size


@facts.fact("pdsgen-test")
def _words(path: Path) -> list[str]:
    READS.append(path.name)
    return path.read_text().split()


@pytest.fixture
def files(tmp_path):
    facts.forget()
    READS.clear()
    paths = []
    for number in range(3):
        path = tmp_path / f"f{number}.txt"
        path.write_text("a b c " * (number + 1))
        paths.append(path)
    yield paths
    facts.forget()


def test_learnt_facts_are_handed_out_once_then_read_here(files):
    for path in files:
        facts.learn(str(path), facts.made(str(path), "pdsgen-test"))  # as a worker makes them
    READS.clear()
    assert [facts.of(_words, path) for path in files] == [["a", "b", "c"] * n for n in (1, 2, 3)]
    assert [facts.of(_size, path) for path in files] == [6, 12, 18]
    assert READS == []  # every answer was learnt
    assert facts.of(_size, files[0]) == 6 and READS == ["f0.txt"]  # handed out once: then read here
    assert facts.asked() == {facts._name(_size), facts._name(_words)}


def test_a_dropped_or_forgotten_file_is_read_again(files):
    for path in files:
        facts.learn(str(path), facts.made(str(path), "pdsgen-test"))
    READS.clear()
    facts.drop(str(files[0]))
    assert facts.of(_size, files[0]) == 6 and READS == ["f0.txt"]
    facts.forget()
    assert facts.of(_size, files[1]) == 12 and READS == ["f0.txt", "f1.txt"] and not facts.asked() - {
        facts._name(_size)}


def test_a_second_lesson_adds_to_the_first(files):
    path = files[2]
    facts.learn(str(path), facts.packed({facts._name(_size): 100}))
    facts.learn(str(path), facts.packed({facts._name(_words): ["x"]}))
    assert facts.of(_size, path) == 100 and facts.of(_words, path) == ["x"] and READS == []


def _child_answer(path: Path, answer) -> None:
    answer.send(facts.of(_size, path))


def test_a_forked_process_does_not_take_its_parents_lessons(files):
    """A process forked from one that learnt (the delivery's checking process is forked before any
    learning, but the rule holds whenever) reads for itself, never from its parent's store."""
    path = files[1]
    facts.learn(str(path), facts.packed({facts._name(_size): 999}))
    context = multiprocessing.get_context("fork")
    receive, send = context.Pipe(duplex=False)
    child = context.Process(target=_child_answer, args=(path, send))
    child.start()
    send.close()
    assert receive.poll(30) and receive.recv() == 12
    child.join()
    assert facts.of(_size, path) == 999
