"""Issue 6, item 4: fuzz the URL query parsing (hypothesis).

Whatever a URL carries, ``parse_query`` returns; what it accepts is valid for
the explorer's state (applying it cannot raise), what it rejects is named in a
short message, and messages never echo a long value back.
"""

import urllib.parse

from hypothesis import HealthCheck, given, settings, strategies as st

from app.state import URL_PARAMETERS, ExplorerState, parse_query

names = st.one_of(st.sampled_from(sorted(URL_PARAMETERS)), st.text(max_size=80))
values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-10**30, 10**30).map(str),
    st.text(max_size=300),
    st.sampled_from(["", "nan", "inf", "-inf", "1e309", "0x10", "1_000", " 0.3 ", "0,3", "true", "None",
                     "strip", "plane", "triangle", "sine", "physical", "normalised", "x" * 5000,
                     "__import__('os')", "${jndi:ldap://x}", "<script>alert(1)</script>", "%00", "0.3\n0.4"]),
)
queries = st.lists(st.tuples(names, values), max_size=12)
FUZZ = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@FUZZ
@given(pairs=queries)
def test_any_query_string_is_parsed_without_raising(pairs):
    query = "?" + urllib.parse.urlencode(pairs)
    updates, errors, ignored = parse_query(query)
    assert set(updates) <= set(URL_PARAMETERS)
    for message in errors:
        assert len(message) <= 400, "a rejected value is not echoed back in full"
    for name in ignored:
        assert name not in URL_PARAMETERS
    state = ExplorerState()
    state.param.update(**updates)  # what was accepted is valid: applying it cannot raise


@FUZZ
@given(mapping=st.dictionaries(names, st.one_of(values, st.lists(values, max_size=4)), max_size=10))
def test_any_mapping_with_repeated_keys_is_parsed_without_raising(mapping):
    updates, errors, ignored = parse_query(mapping)
    ExplorerState().param.update(**updates)
    for key, value in mapping.items():
        if isinstance(value, list) and len(value) > 1 and key in URL_PARAMETERS:
            assert key not in updates or all(v == value[0] for v in value), "repeated keys with different values"


@FUZZ
@given(ft=st.floats(allow_nan=True, allow_infinity=True), w=st.floats(allow_nan=True, allow_infinity=True))
def test_numeric_loads_are_accepted_exactly_in_range(ft, w):
    updates, errors, _ = parse_query({"ft": repr(ft), "w": repr(w)})
    assert ("ft" in updates) == (0.0 <= ft < 1.0)
    assert ("w" in updates) == (0.0 <= w < 1.0)
    assert len(errors) == (not 0.0 <= ft < 1.0) + (not 0.0 <= w < 1.0)
