from pathlib import Path

from gcs.processes.launch import ProcessOptions, agent_command, cameras_command, sim_command


def test_default_ports_keep_qgroundcontrols_14550_free_for_13_vehicles() -> None:
    """With PX4's defaults (14540 + i, GCS 14550) vehicle 11 would land on the GCS port; the launcher skips it."""
    options = ProcessOptions(scenario_arg="circle")
    commands = [agent_command(options, vehicle_id, Path(f"agent_{vehicle_id}.json")) for vehicle_id in range(1, 14)]
    urls = [command[command.index("--mavlink") + 1] for command in commands]
    ports = [int(url.rsplit(":", 1)[1]) for url in urls]
    assert ports[:10] == list(range(14540, 14550))
    assert options.gcs_port == 14550 and 14550 not in ports
    assert len(set(ports)) == 13


def test_children_get_their_plan_file_and_no_scenario() -> None:
    """Every child reads the plan the ground station resolved; none resolves the scenario again."""
    options = ProcessOptions(scenario_arg="circle", overrides=("radio.loss=0.3",), seed=4)
    plan_dir = Path("/runs/x/plan")
    commands = [sim_command(options, plan_dir / "fleet.json"), cameras_command(options, plan_dir / "cameras.json"),
                agent_command(options, 3, plan_dir / "agent_3.json")]
    for command, name in zip(commands, ("fleet.json", "cameras.json", "agent_3.json")):
        assert command[command.index("--plan") + 1] == str(plan_dir / name)
        assert "--scenario" not in command and "--set" not in command
