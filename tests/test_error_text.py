from hsr_handover.error_text import first_line


def test_a_long_message_is_told_by_its_first_line():
    assert first_line(RuntimeError("  solver failed\n  at step 3\n")) == "solver failed"


def test_a_silent_error_is_told_by_its_type():
    assert first_line(KeyError()) == "KeyError"
    assert first_line(ValueError("   ")) == "ValueError"
