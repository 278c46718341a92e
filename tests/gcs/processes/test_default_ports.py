from gcs.processes.launch import ProcessOptions, agent_command


def test_default_ports_keep_qgroundcontrols_14550_free_for_13_vehicles() -> None:
    """With PX4's defaults (14540 + i, GCS 14550) vehicle 11 would land on the GCS port; the launcher skips it."""
    options = ProcessOptions(scenario_arg="circle")
    commands = [agent_command(options, vehicle_id, "boundary", "circle") for vehicle_id in range(1, 14)]
    urls = [command[command.index("--mavlink") + 1] for command in commands]
    ports = [int(url.rsplit(":", 1)[1]) for url in urls]
    assert ports[:10] == list(range(14540, 14550))
    assert options.gcs_port == 14550 and 14550 not in ports
    assert len(set(ports)) == 13
