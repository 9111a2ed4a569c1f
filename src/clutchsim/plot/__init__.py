"""Figures (matplotlib, optional extra ``plot``).  Computing and plotting are separate:
plot functions take results/tables, accept ``ax=``, and return the figure and axes.
Submodules are imported on use so that ``import clutchsim`` never needs matplotlib."""
