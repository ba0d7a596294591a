"""What every object that crosses ROAR_PY's remote protocol has: the message it reads (``_in_msg_type``,
``_depack_info``), the message it writes (``_out_msg_type``, ``_pack_info``) and its work each tick."""
import typing

_InMsgT = typing.TypeVar("_InMsgT")
_OutMsgT = typing.TypeVar("_OutMsgT")


class RoarPyObjectWithRemoteMessage(typing.Generic[_InMsgT, _OutMsgT]):
    def _depack_info(self, data: _InMsgT) -> bool:
        raise NotImplementedError()

    async def _tick_remote(self) -> None:
        return

    def _pack_info(self) -> _OutMsgT:
        raise NotImplementedError()


def register_object_with_remote_message(in_msg_type: type, out_msg_type: type):
    """Class decorator: the message types an object reads and writes."""
    def register(cls):
        cls._in_msg_type = in_msg_type
        cls._out_msg_type = out_msg_type
        return cls

    return register
