from mock_autopilot.ports import onboard_port, onboard_port_range


def test_first_ten_follow_px4_sitl() -> None:
    assert [onboard_port(14540, i, 14550) for i in range(10)] == list(range(14540, 14550))


def test_the_gcs_port_is_skipped() -> None:
    ports = [onboard_port(14540, i, 14550) for i in range(13)]
    assert 14550 not in ports
    assert ports[10:] == [14551, 14552, 14553]
    assert len(set(ports)) == 13
    assert onboard_port_range(14540, 13, 14550) == (14540, 14553)


def test_a_gcs_port_outside_the_range_changes_nothing() -> None:
    assert [onboard_port(25100, i, 25050) for i in range(3)] == [25100, 25101, 25102]
    assert onboard_port(25100, 60, 25150) == 25161
