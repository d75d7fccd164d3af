"""What the stages need from the operating system: atomic outputs, memory, threads, libc.

Nothing here knows about meshes. The modules:

- :mod:`~blockmesh._system.atomic`: outputs built beside their target and committed by one rename;
- :mod:`~blockmesh._system.targets`: output targets checked, OS failures as one located error;
- :mod:`~blockmesh._system.memory`: memory available and held, byte counts for people;
- :mod:`~blockmesh._system.procfs`: the one reader of ``/proc``;
- :mod:`~blockmesh._system.threads`: independent pieces of work on worker threads;
- :mod:`~blockmesh._system.prefault`: fresh output memory made resident ahead of its use;
- :mod:`~blockmesh._system.libc`: functions of the C library already loaded.
"""
