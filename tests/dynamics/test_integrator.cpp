// placeholder: written by the dynamics test pass
