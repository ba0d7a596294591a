"""ROAR_PY's interface, name by name: every public name of ROAR_PY's roar_py_interface (at ROAR_PY's head:
its worlds, actors, sensors, base, wrappers and visualizations packages) exists here, and the methods
ROAR's programs call take ROAR_PY's arguments in ROAR_PY's order (extra trailing keyword arguments
allowed). The backend's names are roar_py_carla's (RoarPyCarlaWorld, RoarPyCarlaActor, RoarPyCarlaVehicle,
RoarPyCarlaInstance). A failure names what is missing or different."""
import dataclasses
import importlib
import inspect

import pytest

import roar_py_interface as rpi
import roar_py_ros

# roar_py_interface's public names, package by package, as ROAR_PY's __init__ files export them.
ROAR_PY_NAMES = {
    "worlds": ["RoarPyWorld", "RoarPyWorldResettable", "RoarPyWaypoint", "RoarPyWaypointsProjection",
               "RoarPyWaypointsTracker", "RoarPyOccupancyMapProducer"],
    "actors": ["RoarPyActor", "RoarPyResettableActor", "RoarPyVehicleAutoGearActor", "RoarPyVehicleManualGearActor"],
    "sensors": ["RoarPyAccelerometerSensor", "RoarPyAccelerometerSensorData", "RoarPyCameraSensor",
                "RoarPyCameraSensorData", "RoarPyCameraSensorDataGreyscale", "RoarPyCameraSensorDataRGB",
                "RoarPyCameraSensorDataDepth", "RoarPyCameraSensorDataSemanticSegmentation",
                "RoarPyCollisionSensor", "RoarPyCollisionSensorData", "RoarPyGNSSSensor", "RoarPyGNSSSensorData",
                "RoarPyGyroscopeSensor", "RoarPyGyroscopeSensorData", "RoarPyFrameQuatSensor",
                "RoarPyFrameQuatSensorData", "RoarPyRollPitchYawSensor", "RoarPyRollPitchYawSensorData",
                "RoarPyFrameQuatSensorFromRollPitchYaw", "RoarPyRollPitchYawSensorFromFrameQuat", "RoarPyLiDARSensor",
                "RoarPyLiDARSensorData", "RoarPyLocationInWorldSensor", "RoarPyLocationInWorldSensorData",
                "RoarPyOccupancyMapSensor", "RoarPyOccupancyMapSensorData", "RoarPyOccupancyMapSensorImpl",
                "RoarPyVelocimeterSensor", "RoarPyVelocimeterSensorData", "RoarPyCustomLambdaSensor",
                "RoarPyCustomLambdaSensorData", "RoarPyRadarSensor", "RoarPyRadarSensorData"],
    "base": ["RoarPySensor", "RoarPyRemoteSupportedSensorData", "RoarPyRemoteSupportedSensorSerializationScheme"],
    "wrappers": ["RoarPyWrapper", "RoarPyActorWrapper", "RoarPySensorWrapper", "RoarPyWorldWrapper",
                 "RoarPyThreadSafeWrapper", "roar_py_thread_sync", "RoarPyAddItemWrapper", "roar_py_append_item",
                 "roar_py_remove_item", "RoarPyActorSensorFilterWrapper"],
    "visualizations": ["RoarPyVisualizer"],
}

# ROAR_PY's modules, each with names ROAR's programs import from it (ROAR_PY's files at its head): of
# roar_py_interface and of roar_py_remote.
ROAR_PY_MODULES = {
    "roar_py_interface.worlds.world": ["RoarPyWorld", "RoarPyWorldResettable"],
    "roar_py_interface.worlds.waypoint": ["RoarPyWaypoint", "RoarPyWaypointsProjection", "RoarPyWaypointsTracker"],
    "roar_py_interface.worlds.occupancy_map": ["RoarPyOccupancyMapProducer"],
    "roar_py_interface.actors.actor": ["RoarPyActor", "RoarPyResettableActor", "propose_name_and_modify_dict",
                                       "propose_name_and_modify_list"],
    "roar_py_interface.actors.vehicle": ["RoarPyVehicleAutoGearActor", "RoarPyVehicleManualGearActor"],
    "roar_py_interface.base.sensor": ["RoarPySensor", "RoarPyRemoteSupportedSensorData",
                                      "RoarPyRemoteSupportedSensorSerializationScheme",
                                      "remote_support_sensor_data_register"],
    "roar_py_interface.sensors.accelerometer_sensor": ["RoarPyAccelerometerSensor", "RoarPyAccelerometerSensorData"],
    "roar_py_interface.sensors.camera_sensor": ["RoarPyCameraSensor", "RoarPyCameraSensorData",
                                                "RoarPyCameraSensorDataGreyscale", "RoarPyCameraSensorDataRGB",
                                                "RoarPyCameraSensorDataDepth",
                                                "RoarPyCameraSensorDataSemanticSegmentation"],
    "roar_py_interface.sensors.collision_sensor": ["RoarPyCollisionSensor", "RoarPyCollisionSensorData"],
    "roar_py_interface.sensors.custom_lambda_sensor": ["RoarPyCustomLambdaSensor", "RoarPyCustomLambdaSensorData"],
    "roar_py_interface.sensors.gnss_sensor": ["RoarPyGNSSSensor", "RoarPyGNSSSensorData"],
    "roar_py_interface.sensors.gyroscope_sensor": ["RoarPyGyroscopeSensor", "RoarPyGyroscopeSensorData"],
    "roar_py_interface.sensors.lidar_sensor": ["RoarPyLiDARSensor", "RoarPyLiDARSensorData"],
    "roar_py_interface.sensors.location_in_world_sensor": ["RoarPyLocationInWorldSensor",
                                                           "RoarPyLocationInWorldSensorData"],
    "roar_py_interface.sensors.occupancy_map_sensor": ["RoarPyOccupancyMapSensor", "RoarPyOccupancyMapSensorData",
                                                       "RoarPyOccupancyMapSensorImpl"],
    "roar_py_interface.sensors.radar_sensor": ["RoarPyRadarSensor", "RoarPyRadarSensorData"],
    "roar_py_interface.sensors.rotation_sensor": ["RoarPyFrameQuatSensor", "RoarPyFrameQuatSensorData",
                                                  "RoarPyRollPitchYawSensor", "RoarPyRollPitchYawSensorData",
                                                  "RoarPyFrameQuatSensorFromRollPitchYaw",
                                                  "RoarPyRollPitchYawSensorFromFrameQuat"],
    "roar_py_interface.sensors.velocimeter_sensor": ["RoarPyVelocimeterSensor", "RoarPyVelocimeterSensorData"],
    "roar_py_interface.wrappers.wrapper_base": ["RoarPyWrapper", "RoarPyActorWrapper", "RoarPySensorWrapper",
                                                "RoarPyWorldWrapper", "RoarPyThreadSafeWrapper", "roar_py_thread_sync",
                                                "RoarPyAddItemWrapper", "roar_py_append_item", "roar_py_remove_item"],
    "roar_py_interface.wrappers.actor_sensor_filter": ["RoarPyActorSensorFilterWrapper"],
    "roar_py_interface.visualizations.visualizer": ["RoarPyVisualizer"],
    "roar_py_remote.actors.remote_actors": ["RoarPyRemoteSharedActor", "RoarPyRemoteClientActor",
                                            "RoarPyRemoteActorObsInfo", "RoarPyRemoteActorObsInfoRequest"],
    "roar_py_remote.actors.remote_actor_wrappers": ["RoarPyRemoteSharedActorWrapper"],
    "roar_py_remote.sensors.remote_sensors": ["RoarPyRemoteSharedSensor"],
    "roar_py_remote.sensors.remote_sensor_wrappers": ["RoarPyRemoteSharedSensorWrapper"],
    "roar_py_remote.worlds.server_worlds": ["RoarPyRemoteMaskedWorld", "RoarPyRemoteServerWorldManager"],
    "roar_py_remote.base.remote_object": ["RoarPyObjectWithRemoteMessage"],
    "roar_py_remote.services.base_service": ["RoarPyStreamingService", "RoarPyStreamingClient"],
    "roar_py_remote.services.common": ["RoarPyRemoteClientWorldWithStreamClient"],
    "roar_py_remote.services.websocket_service": ["RoarPyWebsocketServerService", "RoarPyWebsocketClientService"],
}

# (object, method, ROAR_PY's parameters after self in order, with defaults where it has them: REQUIRED where
# ROAR_PY has none and neither may we, IS_NONE where its default is None, None where that is not checked).
REQUIRED = inspect.Parameter.empty
IS_NONE = type("IsNone", (), {"__repr__": lambda self: "a default of None"})()
SIGNATURES = [
    (rpi.RoarPyActor, "__init__",
     [("name", REQUIRED), ("control_timestep", 0.05), ("force_real_control_timestep", False)]),
    (rpi.RoarPyVehicleAutoGearActor, "__init__",
     [("name", "vehicle_autogear"), ("control_timestep", 0.05), ("force_real_control_timestep", False)]),
    (rpi.RoarPyVehicleManualGearActor, "__init__",
     [("name", "vehicle_manualgear"), ("control_timestep", 0.05), ("force_real_control_timestep", False),
      ("num_gears", 6)]),
    (rpi.RoarPySensor, "__init__", [("name", REQUIRED), ("control_timestep", REQUIRED)]),
    (rpi.RoarPyCameraSensor, "__init__",
     [("name", REQUIRED), ("control_timestep", REQUIRED), ("target_data_type", REQUIRED)]),
    (rpi.RoarPyFrameQuatSensor, "__init__", [("control_timestep", REQUIRED), ("name", "framequat_sensor")]),
    (rpi.RoarPyRollPitchYawSensorFromFrameQuat, "__init__", [("framequat_sensor", REQUIRED), ("name", IS_NONE)]),
    (rpi.RoarPyFrameQuatSensorFromRollPitchYaw, "__init__", [("rpy_sensor", REQUIRED), ("name", IS_NONE)]),
    (rpi.RoarPyOccupancyMapSensor, "__init__", [("name", "occupancy_map_sensor")]),
    (rpi.RoarPyOccupancyMapSensorImpl, "__init__",
     [("producer", None), ("location_sensor", None), ("rotation_sensor", None), ("name", "occupancy_map_sensor")]),
    (rpi.RoarPyCustomLambdaSensor, "__init__",
     [("name", REQUIRED), ("control_timestep", REQUIRED), ("data_space", REQUIRED)]),
    (rpi.RoarPyOccupancyMapProducer, "__init__",
     [("waypoints", None), ("width", None), ("height", None), ("width_world", None), ("height_world", None)]),
    (rpi.RoarPyOccupancyMapProducer, "plot_occupancy_map", [("location_2d", None), ("rotation_yaw", None)]),
    (rpi.RoarPyWaypoint, "__init__", [("location", None), ("roll_pitch_yaw", None), ("lane_width", None)]),
    (rpi.RoarPyWaypointsTracker, "__init__", [("waypoints", None), ("current_traced_index", 0)]),
    (rpi.RoarPyWaypointsTracker, "trace_point", [("point", REQUIRED), ("start_idx", 0)]),
    (rpi.RoarPyWaypointsTracker, "trace_forward_projection", [("projection", REQUIRED), ("distance", REQUIRED)]),
    (rpi.RoarPyWaypointsTracker, "delta_distance_projection", [("projection_origin", REQUIRED),
                                                               ("projection_destination", REQUIRED)]),
    (rpi.RoarPyWaypointsTracker, "get_interpolated_waypoint", [("projection", REQUIRED)]),
    (rpi.RoarPyWaypointsTracker, "total_distance_from_first_waypoint", [("projection_result", REQUIRED)]),
    (rpi.RoarPyWrapper, "__init__", [("wrapped_object", REQUIRED), ("wrapper_name", REQUIRED)]),
    (rpi.RoarPyActorWrapper, "__init__", [("wrapped_object", REQUIRED), ("wrapper_name", "RoarPyActorWrapper")]),
    (rpi.RoarPySensorWrapper, "__init__", [("wrapped_object", REQUIRED), ("wrapper_name", "RoarPySensorWrapper")]),
    (rpi.RoarPyWorldWrapper, "__init__", [("wrapped_object", REQUIRED), ("wrapper_name", "RoarPyWorldWrapper")]),
    (rpi.RoarPyThreadSafeWrapper, "__init__", [("wrapped_object", REQUIRED), ("tslock", REQUIRED)]),
    (rpi.RoarPyAddItemWrapper, "__init__", [("wrapped_object", REQUIRED), ("add_callback", IS_NONE),
                                            ("remove_callback", IS_NONE)]),
    # exclude_sensors: ROAR_PY's default is a shared list ([]); ours an empty tuple, copied into the wrapper's
    # own list, so that a program appending to one wrapper's list does not change another's.
    (rpi.RoarPyActorSensorFilterWrapper, "__init__",
     [("wrapped_object", REQUIRED), ("exclude_sensors", None), ("wrapper_name", "RoarPyActorSensorFilterWrapper")]),
    (rpi.RoarPyVisualizer, "__init__", [("actor", None)]),
    # roar_py_carla's backend.
    (roar_py_ros.RoarPyRosWorld, "spawn_vehicle", [("blueprint_id", None), ("location", None), ("roll_pitch_yaw", None),
                                                   ("auto_gear", True), ("name", "carla_vehicle"), ("rgba", None)]),
    (roar_py_ros.RoarPyRosWorld, "set_control_steps", [("control_timestep", None), ("control_substimestep", None)]),
    (roar_py_ros.RoarPyRosWorld, "set_asynchronous", [("asynchronous", None)]),
    (roar_py_ros.RoarPyRosWorld, "get_geolocation", [("location", None)]),
    (roar_py_ros.RoarPyRosWorld, "attach_camera_sensor",
     [("target_datatype", None), ("location", None), ("roll_pitch_yaw", None), ("fov", 90.0), ("image_width", 800),
      ("image_height", 600), ("control_timestep", 0.0), ("attachment_type", None), ("name", "carla_camera"),
      ("bind_to", None)]),
    (roar_py_ros.RoarPyRosWorld, "remove_actor", [("actor", None)]),
    (roar_py_ros.RoarPyRosWorld, "remove_sensor", [("sensor", None)]),
    (roar_py_ros.RoarPyRosVehicle, "attach_camera_sensor",
     [("target_datatype", None), ("location", None), ("roll_pitch_yaw", None), ("fov", 90.0), ("image_width", 800),
      ("image_height", 600), ("control_timestep", 0.0), ("attachment_type", None), ("name", "carla_camera")]),
    (roar_py_ros.RoarPyRosVehicle, "attach_collision_sensor",
     [("location", None), ("roll_pitch_yaw", None), ("attachment_type", None), ("name", "carla_collision_sensor")]),
    (roar_py_ros.RoarPyRosVehicle, "attach_accelerometer_sensor", [("name", "carla_accelerometer_sensor")]),
    (roar_py_ros.RoarPyRosVehicle, "attach_velocimeter_sensor", [("name", "carla_velocimeter_sensor")]),
    (roar_py_ros.RoarPyRosVehicle, "attach_local_velocimeter_sensor", [("name", "carla_local_velocimeter_sensor")]),
    (roar_py_ros.RoarPyRosVehicle, "attach_gnss_sensor",
     [("noise_altitude_bias", 0.0), ("noise_altitude_std", 0.0), ("noise_latitude_bias", 0.0),
      ("noise_latitude_std", 0.0), ("noise_longitude_bias", 0.0), ("noise_longitude_std", 0.0), ("noise_seed", 0),
      ("control_timestep", 0.0), ("name", "carla_gnss_sensor")]),
    (roar_py_ros.RoarPyRosVehicle, "attach_lidar_sensor",
     [("location", None), ("roll_pitch_yaw", None), ("num_lasers", 32), ("max_distance", 10.0),
      ("points_per_second", 56000), ("rotation_frequency", 10.0), ("upper_fov", 10.0), ("lower_fov", -30.0),
      ("horizontal_fov", 360.0), ("atmosphere_attenuation_rate", 0.004), ("dropoff_general_rate", 0.45),
      ("dropoff_intensity_limit_below", 0.8), ("control_timestep", 0.0), ("noise_std", 0.0),
      ("attachment_type", None), ("name", "carla_lidar_sensor")]),
    (roar_py_ros.RoarPyRosVehicle, "attach_roll_pitch_yaw_sensor", [("name", "carla_rpy_sensor")]),
    (roar_py_ros.RoarPyRosVehicle, "attach_framequat_sensor", [("name", "carla_framequat_sensor")]),
    (roar_py_ros.RoarPyRosVehicle, "attach_gyroscope_sensor", [("name", "carla_gyroscope_sensor")]),
    (roar_py_ros.RoarPyRosVehicle, "attach_location_in_world_sensor", [("name", "carla_location_in_world_sensor")]),
    (roar_py_ros.RoarPyRosVehicle, "attach_occupancy_map_sensor",
     [("width", None), ("height", None), ("width_in_world", None), ("height_in_world", None),
      ("name", "carla_occupancy_map_sensor")]),
    (roar_py_ros.RoarPyRosVehicle, "remove_sensor", [("sensor", None)]),
    (roar_py_ros.RoarPyRosVehicle, "set_transform", [("new_location", None), ("new_rotation", None)]),
    (roar_py_ros.RoarPyRosVehicle, "set_3d_location", [("new_location", None)]),
    (roar_py_ros.RoarPyRosVehicle, "set_roll_pitch_yaw", [("new_rotation_rpy", None)]),
    (roar_py_ros.RoarPyRosVehicle, "set_linear_3d_velocity", [("target_linear_velocity", None)]),
    (roar_py_ros.RoarPyRosVehicle, "set_angular_velocity", [("target_angular_velocity", None)]),
    (roar_py_ros.RoarPyRosInstance, "load_world", [("map_name", None), ("reset_settings", True)]),
    (roar_py_ros.RoarPyRosInstance, "reload_world", [("reset_settings", True)]),
]

# roar_py_carla's methods and properties that ROAR's programs use, on each backend class.
BACKEND_MEMBERS = {
    roar_py_ros.RoarPyRosWorld: ["is_asynchronous", "get_actors", "get_sensors", "maneuverable_waypoints",
                                 "comprehensive_waypoints", "last_tick_elapsed_seconds", "step", "spawn_points",
                                 "control_timestep", "contorl_subtimestep", "map_name", "attach_lidar_sensor"],
    roar_py_ros.RoarPyRosVehicle: ["get_3d_location", "get_roll_pitch_yaw", "get_linear_3d_velocity",
                                   "get_angular_velocity", "get_acceleration", "bounding_box", "get_action_spec",
                                   "apply_action", "receive_observation", "get_last_observation",
                                   "get_gym_observation_spec", "get_last_gym_observation", "convert_obs_to_gym_obs",
                                   "get_sensors", "reset", "close", "is_closed", "num_gears", "auto_gear",
                                   "control_timestep", "force_real_control_timestep"],
    roar_py_ros.RoarPyRosInstance: ["world", "get_available_maps", "get_client_version", "get_server_version",
                                    "close", "is_closed"],
}


@pytest.mark.parametrize("package", sorted(ROAR_PY_NAMES))
def test_every_public_name_of_roar_py_is_here(package):
    missing = [name for name in ROAR_PY_NAMES[package] if not hasattr(rpi, name)]
    assert missing == [], f"roar_py_interface ({package}) lacks {missing}"


@pytest.mark.parametrize("module", sorted(ROAR_PY_MODULES))
def test_roar_pys_module_paths_import_with_their_names(module):
    """`from roar_py_interface.worlds.waypoint import RoarPyWaypoint` and the like, as ROAR's programs write."""
    imported, package = importlib.import_module(module), importlib.import_module(module.split(".")[0])
    missing = [name for name in ROAR_PY_MODULES[module] if getattr(imported, name, None) is not getattr(package, name)]
    assert missing == [], f"{module} lacks {missing} (or holds other objects than {package.__name__}'s)"


def test_the_count_of_roar_py_names():
    # ROAR_PY's 53 public classes, the projection's namedtuple and the three wrappers' marking functions.
    names = [getattr(rpi, name) for names in ROAR_PY_NAMES.values() for name in names]
    classes = [n for n in names if isinstance(n, type) and not issubclass(n, tuple)]
    assert len(names) == 57 and len(classes) == 53


@pytest.mark.parametrize("owner,method,expected", SIGNATURES,
                         ids=[f"{o.__name__}.{m}" for o, m, _ in SIGNATURES])
def test_methods_take_roar_pys_arguments_in_order(owner, method, expected):
    parameters = [p for p in inspect.signature(getattr(owner, method)).parameters.values() if p.name != "self"]
    names = [p.name for p in parameters]
    assert names[:len(expected)] == [name for name, _ in expected], f"{owner.__name__}.{method}{tuple(names)}"
    for parameter, (name, default) in zip(parameters, expected):
        if default is REQUIRED:
            assert parameter.default is REQUIRED, f"{owner.__name__}.{method}: {name} has a default ROAR_PY's has not"
        elif default is IS_NONE:
            assert parameter.default is None, f"{owner.__name__}.{method}: {name} defaults to {parameter.default!r}"
        elif default is not None:
            assert parameter.default == default, f"{owner.__name__}.{method}: {name} defaults to {parameter.default!r}"
    for extra in parameters[len(expected):]:
        assert extra.default is not inspect.Parameter.empty, f"{owner.__name__}.{method}: extra '{extra.name}' required"


# ROAR_PY's sensor data classes: their fields in order, none with a default (a program builds them whole).
DATA_FIELDS = {
    rpi.RoarPyCameraSensorDataRGB: ["image_rgb"],
    rpi.RoarPyCameraSensorDataGreyscale: ["image_greyscale"],
    rpi.RoarPyCameraSensorDataDepth: ["image_depth", "is_log_scale"],
    rpi.RoarPyCameraSensorDataSemanticSegmentation: ["image_ss", "ss_label_color_map"],
    rpi.RoarPyCustomLambdaSensorData: ["flattened", "space"],
}


@pytest.mark.parametrize("owner", list(DATA_FIELDS), ids=lambda o: o.__name__)
def test_sensor_data_classes_have_roar_pys_fields_without_defaults(owner):
    fields = dataclasses.fields(owner)
    assert [f.name for f in fields] == DATA_FIELDS[owner]
    defaulted = [f.name for f in fields if f.default is not dataclasses.MISSING
                 or f.default_factory is not dataclasses.MISSING]
    assert defaulted == [], f"{owner.__name__}: {defaulted} have defaults ROAR_PY's have not"


@pytest.mark.parametrize("owner", list(BACKEND_MEMBERS), ids=lambda o: o.__name__)
def test_the_backend_has_roar_py_carlas_members(owner):
    missing = [name for name in BACKEND_MEMBERS[owner] if not hasattr(owner, name) and
               name not in getattr(owner, "__annotations__", {}) and name not in ("bounding_box", "auto_gear", "world")]
    assert missing == [], f"{owner.__name__} lacks {missing}"


def test_the_lidar_interface_has_roar_pys_properties():
    for name in ("num_lasers", "max_distance", "min_distance", "points_per_second", "rotation_frequency", "upper_fov",
                 "lower_fov", "horizontal_fov"):
        assert isinstance(getattr(rpi.RoarPyLiDARSensor, name, None), property), name


def test_roar_pys_hooks_and_setters_are_where_roar_py_has_them():
    assert hasattr(rpi.RoarPyResettableActor, "_RoarPyResettableActor__reset"), "ROAR_PY's name-mangled reset hook"
    assert rpi.RoarPyWorldWrapper.is_asynchronous.fset is not None, "RoarPyWorldWrapper.is_asynchronous is settable"
