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


def test_agents_on_other_hosts_reach_the_fleet_and_the_hub_routes() -> None:
    """``--no-agents --fleet-bind 0.0.0.0 --onboard-partner``: the fleet gets the addresses, the hub is a router."""
    from gcs.mission.cli import parse_options
    from gcs.processes import process_options
    from gcs.processes.launch import hub_config
    from gcs.scenario import load_scenario

    mission = parse_options(["circle", "--no-agents", "--fleet-bind", "0.0.0.0", "--onboard-partner", "1-7=10.0.0.2",
                             "--onboard-partner", "8-13=10.0.1.2"])
    options = process_options(load_scenario("circle"), mission)
    command = sim_command(options, Path("fleet.json"))
    assert command[command.index("--bind") + 1] == "0.0.0.0"
    assert [command[i + 1] for i, a in enumerate(command) if a == "--onboard-partner"] == ["1-7=10.0.0.2", "8-13=10.0.1.2"]
    assert not options.start_agents and hub_config(options).mode == "router"
    assert hub_config(ProcessOptions(scenario_arg="circle")).mode == "peer"
    assert "--bind" not in sim_command(ProcessOptions(scenario_arg="circle"), Path("fleet.json"))
