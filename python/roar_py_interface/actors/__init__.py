"""ROAR_PY's actors: the actor a backend implements and its vehicles."""
from .actor import (RoarPyActor, RoarPyGymObservation, RoarPyObservation, RoarPyResettableActor, observation_keys,  # noqa: F401
                    propose_name_and_modify_dict, propose_name_and_modify_list)
from .vehicle import (RoarPyBaseVehicle, RoarPyVehicleAutoGearActor, RoarPyVehicleManualGearActor,  # noqa: F401
                      vehicle_action_spec)
