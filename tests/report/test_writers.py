"""Every workflow has a report writer."""
from salkit.report.writers import WRITERS
from salkit.systems import WORKFLOWS


def test_a_writer_for_every_workflow():
    systems = {"sal": "airborne"}
    assert {systems.get(k, k) for k in WORKFLOWS} | {"sweep"} == set(WRITERS)  # and the design studies' page
