import pytest

from mock_autopilot.ports import LinkHosts, link_hosts, onboard_port, onboard_port_range, parse_onboard_partners


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


def test_onboard_partners_send_each_vehicle_to_its_companion_computer() -> None:
    hosts = link_hosts("0.0.0.0", ["1-3=10.216.1.2", "4,6=10.216.2.2"])
    assert hosts.bind_host == "0.0.0.0"
    assert [hosts.onboard_host(v) for v in range(1, 8)] == ["10.216.1.2"] * 3 + ["10.216.2.2", "127.0.0.1",
                                                                                 "10.216.2.2", "127.0.0.1"]
    assert LinkHosts().bind_host == LinkHosts().onboard_host(1) == "127.0.0.1"


@pytest.mark.parametrize("spec", ["1-3", "x=10.0.0.1", "1=not-an-ip", "=10.0.0.1", "2-1x=10.0.0.1"])
def test_a_bad_partner_or_bind_address_names_the_option(spec: str) -> None:
    with pytest.raises(ValueError, match="--onboard-partner"):
        parse_onboard_partners([spec])
    with pytest.raises(ValueError, match="--bind"):
        link_hosts("localhost", [])


def test_partners_on_other_hosts_need_a_fleet_bound_beyond_loopback() -> None:
    with pytest.raises(ValueError, match="--bind 127.0.0.1: a loopback socket cannot reach"):
        link_hosts(None, ["1-2=10.216.1.2"])
    assert link_hosts(None, ["1=127.0.0.2"]).onboard_host(1) == "127.0.0.2"
    assert link_hosts("10.216.1.1", ["1=10.216.1.2"]).bind_host == "10.216.1.1"
