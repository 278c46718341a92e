from gcs.relay_refusals import refused_copies_line


def test_honest_run_with_the_station_outside_the_radio() -> None:
    assert refused_copies_line([1, 2, 3], [0, 0, 0], None) == "relayed copies refused as impossible: 0 by the vehicles"


def test_refusing_vehicles_unknown_ones_and_the_ground_node_are_named() -> None:
    line = refused_copies_line([1, 2, 3, 4], [0, 5, None, 2], 3)
    assert line == ("relayed copies refused as impossible: 7 by the vehicles (2: 5, 4: 2), unknown for vehicles 3 "
                    "(no exit report), 3 by the ground station's radio node")
